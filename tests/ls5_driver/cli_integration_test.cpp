// `rangekit ls5 ...` end to end against `rangekit sim ls5` on a real pty and
// loopback UDP: every subcommand, refusals and exit codes, reconnect after the
// emulator is killed and restarted on the same path, config save/diff/load.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>

#include "child_process.hpp"
#include "cli/commands.hpp"
#include "cli_process.hpp"
#include "rangekit/core/udp.hpp"

using namespace ls5_driver_test;
namespace cli = rangekit::cli;

namespace {

struct Workspace {
  std::filesystem::path dir;
  std::string port;
  explicit Workspace(const std::string& name) {
    dir = std::filesystem::temp_directory_path() / ("rangekit-ls5host-" + name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    port = (dir / "ls5").string();
    // A still target mid-range with no noise: code 25000 on a 0/100 sensor (formula 8.5).
    std::ofstream(dir / "scene.toml") << "[target]\nposition_mm = 50.0\nnoise_mm = 0.0\n";
  }
  ~Workspace() { std::filesystem::remove_all(dir); }
  [[nodiscard]] std::string scene() const { return (dir / "scene.toml").string(); }
  CliRun ls5(std::vector<std::string> arguments) const {
    arguments.insert(arguments.begin(), "ls5");
    return run_cli(dir, arguments);
  }
};

std::vector<std::string> sim_arguments(const Workspace& w, std::vector<std::string> extra = {}) {
  std::vector<std::string> arguments{"sim",       "ls5",      "--port",   w.port, "--model", "0/100",
                                     "--version", "LS5.12.0", "--serial", "157",  "--scene", w.scene()};
  arguments.insert(arguments.end(), extra.begin(), extra.end());
  return arguments;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::size_t count_of(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

}  // namespace

// L55: table 9.2 "Network address ... Default values (HEX) 01"; DF restores it, so a
// sensor at 05 answers at 01 afterwards and the CLI says so.
TEST(Ls5Cli, DefaultsMoveTheSensorToAddress01AndSaySoL55) {
  Workspace w("defaults-address");
  Child sim(sim_arguments(w, {"--address", "5"}));
  ASSERT_TRUE(contains(sim.read_line(), "ready:"));
  CliRun defaults = w.ls5({"defaults", "--port", w.port, "--address", "5"});
  ASSERT_EQ(defaults.exit_code, cli::exit_ok) << defaults.err;
  EXPECT_TRUE(contains(defaults.out, "now answers at address 1")) << defaults.out;
  EXPECT_EQ(w.ls5({"info", "--port", w.port, "--address", "1"}).exit_code, cli::exit_ok);
  EXPECT_EQ(w.ls5({"info", "--port", w.port, "--address", "5", "--timeout-ms", "100"}).exit_code, cli::exit_no_reply);
}

TEST(Ls5Cli, DeviceSubcommandsEndToEnd) {
  Workspace w("device");
  Child sim(sim_arguments(w));
  ASSERT_TRUE(contains(sim.read_line(), "ready:"));

  CliRun info = w.ls5({"info", "--port", w.port});
  ASSERT_EQ(info.exit_code, cli::exit_ok) << info.err;
  EXPECT_TRUE(contains(info.out, "serial=157")) << info.out;
  EXPECT_TRUE(contains(info.out, "range-mm=100")) << info.out;
  EXPECT_TRUE(contains(info.out, "ethernet=yes")) << info.out;

  CliRun refused = w.ls5({"set", "--port", w.port, "median-points=4"});
  EXPECT_EQ(refused.exit_code, cli::exit_usage);
  EXPECT_TRUE(contains(refused.err, "1, 3, ..., 49")) << refused.err;

  CliRun set = w.ls5({"set", "--port", w.port, "median-points=7", "pre-filter=median", "analog-lower-mm=12.5"});
  ASSERT_EQ(set.exit_code, cli::exit_ok) << set.err;
  CliRun get = w.ls5({"get", "--port", w.port, "median-points", "0B", "analog-lower"});
  ASSERT_EQ(get.exit_code, cli::exit_ok) << get.err;
  // 12.5 mm of 100 mm is code 6250 (formula 8.5); 0B = 01 is median filtering.
  EXPECT_EQ(get.out, "median-points=7\n0B=01\nanalog-lower=6250\n");

  CliRun raw = w.ls5({"set", "--port", w.port, "0C=04"});
  ASSERT_EQ(raw.exit_code, cli::exit_ok) << raw.err;
  CliRun all = w.ls5({"get", "--port", w.port});
  ASSERT_EQ(all.exit_code, cli::exit_ok) << all.err;
  EXPECT_TRUE(contains(all.out, "averaging-points=4\n")) << all.out;
  EXPECT_TRUE(contains(all.out, "analog-lower-mm=12.5\n")) << all.out;
  EXPECT_TRUE(contains(all.out, "udp-auto-stream=on\n")) << all.out;

  CliRun measure = w.ls5({"measure", "--port", w.port});
  ASSERT_EQ(measure.exit_code, cli::exit_ok) << measure.err;
  EXPECT_TRUE(contains(measure.out, "code=25000 distance_mm=50.0000 signal=ok")) << measure.out;
  CliRun latch = w.ls5({"latch", "--port", w.port});
  ASSERT_EQ(latch.exit_code, cli::exit_ok) << latch.err;
  EXPECT_TRUE(contains(latch.out, "code=25000")) << latch.out;
  CliRun latched = w.ls5({"latch", "--port", w.port, "--read-only"});
  EXPECT_EQ(latched.out, latch.out);

  // The ULS's verbs start/stop/reset and option --timeout work here too, and say the same words.
  EXPECT_EQ(w.ls5({"stop", "--port", w.port, "--timeout", "300"}).out, "stopped\n");
  EXPECT_EQ(w.ls5({"stop", "--port", w.port}).out, "stopped\n");  // from any state
  EXPECT_EQ(w.ls5({"start", "--port", w.port}).out, "measuring\n");
  EXPECT_EQ(w.ls5({"off", "--port", w.port}).exit_code, cli::exit_ok);
  EXPECT_EQ(w.ls5({"on", "--port", w.port}).exit_code, cli::exit_ok);
  EXPECT_EQ(w.ls5({"save", "--port", w.port}).exit_code, cli::exit_ok);
  CliRun defaults = w.ls5({"defaults", "--port", w.port});
  ASSERT_EQ(defaults.exit_code, cli::exit_ok) << defaults.err;
  EXPECT_EQ(w.ls5({"get", "--port", w.port, "median-points"}).out, "median-points=5\n") << "table 9.2 default";

  CliRun nobody = w.ls5({"info", "--port", w.port, "--address", "3", "--timeout-ms", "100"});
  EXPECT_EQ(nobody.exit_code, cli::exit_no_reply);
  for (const char* hint : {"--port", "--baud", "--address 3"}) EXPECT_TRUE(contains(nobody.err, hint)) << nobody.err;
  CliRun no_port = w.ls5({"info", "--port", (w.dir / "nothing").string()});
  EXPECT_EQ(no_port.exit_code, cli::exit_io) << no_port.err;
  CliRun unknown = w.ls5({"get", "--port", w.port, "no-such-setting"});
  EXPECT_EQ(unknown.exit_code, cli::exit_usage) << unknown.err;
  EXPECT_EQ(w.ls5({"info", "--port", w.port, "--address", "0"}).exit_code, cli::exit_usage);
}

// L28 through the CLI: a baud write's echo comes back at the old speed, so `set`
// succeeds; written last whatever the order given, so the other settings still go
// out at the old speed; the sensor then answers at the new one.
TEST(Ls5Cli, SetBaudWithOtherSettingsWritesTheLinkSettingLast) {
  Workspace w("baud");
  Child sim(sim_arguments(w));
  ASSERT_TRUE(contains(sim.read_line(), "ready:"));
  CliRun set = w.ls5({"set", "--port", w.port, "baud-rate=230400", "median-points=5"});
  ASSERT_EQ(set.exit_code, cli::exit_ok) << set.err;
  EXPECT_EQ(set.out, "median-points=5\nbaud-rate=230400\n");
  EXPECT_TRUE(contains(set.err, "note: baud-rate applies from the next request")) << set.err;
  CliRun old_speed = w.ls5({"info", "--port", w.port, "--timeout-ms", "300"});
  EXPECT_EQ(old_speed.exit_code, cli::exit_no_reply) << old_speed.out;
  CliRun fast = w.ls5({"get", "--port", w.port, "--baud", "230400", "median-points", "baud-rate"});
  ASSERT_EQ(fast.exit_code, cli::exit_ok) << fast.err;
  EXPECT_EQ(fast.out, "median-points=5\nbaud-rate=230400\n");
}

TEST(Ls5Cli, SerialStreamAndUdpThroughTheStreamRunner) {
  Workspace w("stream");
  // A free loopback port for the UDP destination.
  std::uint16_t udp_port = 0;
  {
    auto probe = rangekit::UdpSocket::bind(rangekit::Endpoint{"127.0.0.1", 0});
    ASSERT_TRUE(probe);
    udp_port = probe->local_endpoint().port;
  }
  const std::string udp = "127.0.0.1:" + std::to_string(udp_port);
  Child sim(sim_arguments(w, {"--udp", udp, "--time-scale", "10"}));
  ASSERT_TRUE(contains(sim.read_line(), "ready:"));

  CliRun csv = w.ls5({"stream", "--port", w.port, "--count", "5", "--format", "csv", "--thinning", "2"});
  ASSERT_EQ(csv.exit_code, cli::exit_ok) << csv.err;
  EXPECT_EQ(count_of(csv.out, "\n"), 6U) << csv.out;  // header + 5 records
  EXPECT_TRUE(contains(csv.out.substr(0, csv.out.find('\n')), "code")) << csv.out;
  EXPECT_EQ(count_of(csv.out, ",25000,"), 5U) << csv.out;
  EXPECT_EQ(w.ls5({"get", "--port", w.port, "thinning"}).out, "thinning=2\n");

  // 168 records per packet (§10.1): 200 records need two packets.
  CliRun packets = w.ls5({"udp", "--udp-listen", udp, "--count", "200", "--format", "jsonl", "--duration", "60"});
  ASSERT_EQ(packets.exit_code, cli::exit_ok) << packets.err;
  EXPECT_EQ(count_of(packets.out, "\"device\":\"ls5\""), 200U) << packets.err;
  EXPECT_TRUE(contains(packets.out, "\"signal\":\"ok\"")) << packets.out.substr(0, 400);

  CliRun bad_listen = w.ls5({"udp", "--udp-listen", "not-an-endpoint"});
  EXPECT_EQ(bad_listen.exit_code, cli::exit_usage) << bad_listen.err;
}

// No silent waits (docs/cli.md): `ls5 udp` with nothing arriving hints at the
// destination IP/port after 3 s. Nothing sends here; the test reads stderr until the
// hint comes (a blocking read, no timing bound) and then ends the receiver.
TEST(Ls5Cli, UdpWithNothingArrivingHintsAtTheDestination) {
  const int probe = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(probe, 0);
  sockaddr_in any{};
  any.sin_family = AF_INET;
  any.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof any;
  ASSERT_EQ(::bind(probe, reinterpret_cast<sockaddr*>(&any), sizeof any), 0);
  ASSERT_EQ(::getsockname(probe, reinterpret_cast<sockaddr*>(&any), &length), 0);
  const std::string port = std::to_string(ntohs(any.sin_port));
  ::close(probe);  // a free loopback port for the receiver

  int err[2];
  ASSERT_EQ(::pipe2(err, O_CLOEXEC), 0);
  const pid_t pid = rangekit::test::fork_child();
  if (pid == 0) {
    ::dup2(err[1], STDERR_FILENO);
    Child::exec({"ls5", "udp", "--udp-listen", "127.0.0.1:" + port, "--duration", "600"});
  }
  ::close(err[1]);
  FILE* stderr_of_udp = ::fdopen(err[0], "r");
  char buffer[1024];
  const char* got = std::fgets(buffer, sizeof buffer, stderr_of_udp);
  rangekit::test::end_child(pid);
  std::fclose(stderr_of_udp);
  ASSERT_NE(got, nullptr);
  const std::string hint = buffer;
  EXPECT_TRUE(contains(hint, "nothing has arrived on 127.0.0.1:" + port + " for 3 s")) << hint;
  EXPECT_TRUE(contains(hint, "destination IP address")) << hint;
  EXPECT_TRUE(contains(hint, "destination port " + port)) << hint;
}

// `--no-reconnect`, as for the ULS: the stream ends when the port goes
// away, with exit 8 ("the link went away and did not come back", docs/cli.md).
TEST(Ls5Cli, NoReconnectEndsTheStreamWhenThePortGoesAway) {
  Workspace w("no-reconnect");
  auto sim = std::make_unique<Child>(sim_arguments(w));
  ASSERT_TRUE(contains(sim->read_line(), "ready:"));
  Child stream({"ls5", "stream", "--port", w.port, "--format", "jsonl", "--duration", "600", "--no-reconnect"});
  ASSERT_TRUE(contains(stream.read_line(), "\"event\":\"connected\""));  // L69: the first line
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(contains(stream.read_line(), "\"code\":25000"));
  sim->terminate();
  EXPECT_EQ(sim->wait(), 0);
  EXPECT_EQ(stream.wait(), cli::exit_link_lost);
}

// docs/conformance.md L43
TEST(Ls5Cli, StreamSurvivesTheEmulatorBeingKilledAndRestartedOnTheSamePath) {
  Workspace w("reconnect");
  auto sim = std::make_unique<Child>(sim_arguments(w));
  ASSERT_TRUE(contains(sim->read_line(), "ready:"));
  Child stream({"ls5", "stream", "--port", w.port, "--format", "jsonl", "--duration", "60", "--reconnect-ms", "100"});
  ASSERT_TRUE(contains(stream.read_line(), "\"event\":\"connected\""));  // L69: the first line
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(contains(stream.read_line(), "\"code\":25000"));

  sim->terminate();  // the pty and its symlink vanish: as a cable pulled
  EXPECT_EQ(sim->wait(), 0);
  std::string line = stream.read_line();
  while (!line.empty() && !contains(line, "\"event\"")) line = stream.read_line();  // records in flight
  EXPECT_TRUE(contains(line, "\"event\":\"disconnected\"")) << line;

  sim = std::make_unique<Child>(sim_arguments(w));
  ASSERT_TRUE(contains(sim->read_line(), "ready:"));
  for (line = stream.read_line(); !line.empty() && !contains(line, "\"event\""); line = stream.read_line()) {
  }
  EXPECT_TRUE(contains(line, "\"event\":\"reconnected\"")) << line;
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(contains(stream.read_line(), "\"code\":25000"));
  stream.terminate();  // as Ctrl-C
  EXPECT_EQ(stream.wait(), cli::exit_interrupted);
}

// docs/conformance.md L47
TEST(Ls5Cli, ConfigSaveChangeDiffLoadVerify) {
  Workspace w("config");
  Child sim(sim_arguments(w));
  ASSERT_TRUE(contains(sim.read_line(), "ready:"));
  const std::string file = (w.dir / "ls5.toml").string();

  CliRun saved = w.ls5({"config", "save", "--port", w.port, file});
  ASSERT_EQ(saved.exit_code, cli::exit_ok) << saved.err;
  const std::string text = read_file(file);
  EXPECT_TRUE(contains(text, "median-points = 5\n")) << text;
  EXPECT_TRUE(contains(text, "period-ms = 10  # ms")) << text;
  EXPECT_TRUE(contains(text, "s/n") || contains(text, "serial 157")) << text;

  EXPECT_EQ(w.ls5({"config", "diff", "--port", w.port, file}).exit_code, 0);
  ASSERT_EQ(w.ls5({"set", "--port", w.port, "median-points=9", "period-ms=2.5"}).exit_code, cli::exit_ok);
  CliRun diff = w.ls5({"config", "diff", "--port", w.port, file});
  EXPECT_EQ(diff.exit_code, 1);
  EXPECT_TRUE(contains(diff.out, "median-points: file=5 device=9")) << diff.out;
  EXPECT_TRUE(contains(diff.out, "period-ms: file=10 device=2.5")) << diff.out;
  EXPECT_EQ(count_of(diff.out, "\n"), 3U) << diff.out;  // and "2 of N settings differ"

  CliRun loaded = w.ls5({"config", "load", "--port", w.port, file});
  ASSERT_EQ(loaded.exit_code, cli::exit_ok) << loaded.err << loaded.out;
  EXPECT_TRUE(contains(loaded.out, "verified")) << loaded.out;
  EXPECT_TRUE(contains(loaded.out, "skipped baud-rate")) << loaded.out;
  EXPECT_EQ(w.ls5({"get", "--port", w.port, "median-points", "period-ms"}).out, "median-points=5\nperiod-ms=10\n");
  EXPECT_EQ(w.ls5({"config", "diff", "--port", w.port, file}).exit_code, 0);

  // A file with a value out of range is refused before anything is sent.
  std::ofstream((w.dir / "bad.toml").string()) << "[parameters]\nmedian-points = 9\nthinning = 0\n";
  CliRun bad = w.ls5({"config", "load", "--port", w.port, (w.dir / "bad.toml").string()});
  EXPECT_EQ(bad.exit_code, cli::exit_usage) << bad.err;
  EXPECT_TRUE(contains(bad.err, "thinning")) << bad.err;
  EXPECT_EQ(w.ls5({"get", "--port", w.port, "median-points"}).out, "median-points=5\n") << "nothing was written";

  // An empty file is refused as `uls config load` refuses it (exit 3), nothing sent: a
  // "0 settings written, verified" would hide a wrong or truncated file.
  std::ofstream((w.dir / "empty.toml").string()) << "";
  CliRun empty = w.ls5({"config", "load", "--port", w.port, (w.dir / "empty.toml").string()});
  EXPECT_EQ(empty.exit_code, cli::exit_bad_input) << empty.err;
  EXPECT_TRUE(contains(empty.err, "empty.toml: no settings in [link] or [parameters]; nothing to load")) << empty.err;
  EXPECT_FALSE(contains(empty.out, "verified")) << empty.out;
}

// docs/conformance.md L60. §8.9 formula 8.2 with «Type of preliminary result» = 0x01: a
// still target has derivative code 25000, which is 0 mm, not the 50 mm of formula 8.1,
// and the output says it is a derivative (measure, latch and stream alike).
TEST(Ls5Cli, DerivativeIsPrintedAsADerivativeL60) {
  Workspace w("derivative");
  Child sim(sim_arguments(w));
  ASSERT_TRUE(contains(sim.read_line(), "ready:"));
  ASSERT_EQ(w.ls5({"set", "--port", w.port, "result-type=derivative"}).exit_code, cli::exit_ok);

  CliRun measure = w.ls5({"measure", "--port", w.port});
  ASSERT_EQ(measure.exit_code, cli::exit_ok) << measure.err;
  EXPECT_EQ(measure.out, "code=25000 derivative_mm=0.0000 signal=ok\n");
  CliRun latch = w.ls5({"latch", "--port", w.port});
  ASSERT_EQ(latch.exit_code, cli::exit_ok) << latch.err;
  EXPECT_EQ(latch.out, "code=25000 derivative_mm=0.0000 signal=ok\n");
  // Table 3.1: a 100 mm range has a discreteness of 0.001 mm (L63).
  CliRun stream = w.ls5({"stream", "--port", w.port, "--count", "2", "--format", "jsonl"});
  ASSERT_EQ(stream.exit_code, cli::exit_ok) << stream.err;
  EXPECT_EQ(count_of(stream.out, R"("kind":"derivative","code":25000,"derivative_mm":0.000,"signal":"ok")"), 2U)
      << stream.out;
  EXPECT_FALSE(contains(stream.out, "distance_mm")) << stream.out;
}

// docs/conformance.md L61, L62. §8.10: "The values of the lower and upper bounds can only
// be in the range 0÷50000." Raw writes are checked on the combined value: with the
// default upper limit 0xC350 on the sensor, 13=FF alone would make 0xC3FF = 50175; given
// together, 19=C3 and 18=FF make the same; 13=FF with 14=00 makes 255 and is written
// high byte first (never 50175 in between).
TEST(Ls5Cli, RawWritesAreCheckedOnTheCombinedValueL61) {
  Workspace w("combined");
  Child sim(sim_arguments(w));
  ASSERT_TRUE(contains(sim.read_line(), "ready:"));
  CliRun alone = w.ls5({"set", "--port", w.port, "13=FF"});
  EXPECT_EQ(alone.exit_code, cli::exit_usage) << alone.out;
  EXPECT_TRUE(contains(alone.err, "50175")) << alone.err;
  CliRun split = w.ls5({"set", "--port", w.port, "19=C3", "18=FF"});
  EXPECT_EQ(split.exit_code, cli::exit_usage) << split.out;
  EXPECT_TRUE(contains(split.err, "50175")) << split.err;
  EXPECT_EQ(w.ls5({"get", "--port", w.port, "analog-upper", "output1-second-swing"}).out,
            "analog-upper=50000\noutput1-second-swing=50000\n")
      << "nothing was written";

  CliRun both = w.ls5({"set", "--port", w.port, "13=FF", "14=00"});
  ASSERT_EQ(both.exit_code, cli::exit_ok) << both.err;
  EXPECT_EQ(w.ls5({"get", "--port", w.port, "analog-upper"}).out, "analog-upper=255\n");
}

// docs/conformance.md L84. Table 9.3: "The upper limit of the analog output is 50000 (0xC350)
// #01W1350<cr> #01W14C3<cr>", low byte first. From 50000 to 25000 (0x61A8) and back, the bytes
// given in table 9.3's order or the reverse reach the emulator and end at the value they make.
TEST(Ls5Cli, RawBytesInTable93OrderOrTheReverseReachTheValueL84) {
  Workspace w("pairs");
  Child sim(sim_arguments(w));
  ASSERT_TRUE(contains(sim.read_line(), "ready:"));
  CliRun low_first = w.ls5({"set", "--port", w.port, "13=A8", "14=61"});
  ASSERT_EQ(low_first.exit_code, cli::exit_ok) << low_first.err;
  EXPECT_EQ(w.ls5({"get", "--port", w.port, "analog-upper"}).out, "analog-upper=25000\n");
  CliRun back = w.ls5({"set", "--port", w.port, "13=50", "14=C3"});
  ASSERT_EQ(back.exit_code, cli::exit_ok) << back.err;
  EXPECT_EQ(w.ls5({"get", "--port", w.port, "analog-upper"}).out, "analog-upper=50000\n");
  CliRun high_first = w.ls5({"set", "--port", w.port, "14=61", "13=A8"});
  ASSERT_EQ(high_first.exit_code, cli::exit_ok) << high_first.err;
  EXPECT_EQ(w.ls5({"get", "--port", w.port, "analog-upper"}).out, "analog-upper=25000\n");
  CliRun alone = w.ls5({"set", "--port", w.port, "14=C3"});  // C3A8 = 50088 unless 13 comes with it
  EXPECT_EQ(alone.exit_code, cli::exit_usage) << alone.out;
  EXPECT_TRUE(contains(alone.err, "same command (13=..)")) << alone.err;
}

// docs/conformance.md L63. Table 5.1: the 0.5/5 sensor has a discreteness of 0.0001 mm;
// code 21124 is 5 × 21124 / 50000 = 2.1124 mm (formula 8.1), and every output form,
// the capture and its replay keep the four decimals.
TEST(Ls5Cli, StreamKeepsTheSensorsDiscretenessL63) {
  Workspace w("precision");
  // Lower boundary 0.5 mm: the target at 2.6124 mm is 2.1124 mm into the range.
  std::ofstream(w.scene()) << "[target]\nposition_mm = 2.6124\nnoise_mm = 0.0\n";
  Child sim({"sim", "ls5", "--port", w.port, "--model", "0.5/5", "--version", "LS5.12.0", "--scene", w.scene()});
  ASSERT_TRUE(contains(sim.read_line(), "ready:"));
  const std::string capture = (w.dir / "run.sqlite").string();
  CliRun jsonl = w.ls5({"stream", "--port", w.port, "--count", "2", "--format", "jsonl", "--capture", capture});
  ASSERT_EQ(jsonl.exit_code, cli::exit_ok) << jsonl.err;
  EXPECT_EQ(count_of(jsonl.out, R"("code":21124,"distance_mm":2.1124,"signal":"ok")"), 2U) << jsonl.out;
  CliRun csv = w.ls5({"stream", "--port", w.port, "--count", "2", "--format", "csv"});
  ASSERT_EQ(csv.exit_code, cli::exit_ok) << csv.err;
  EXPECT_EQ(count_of(csv.out, ",21124,2.1124,ok"), 2U) << csv.out;
  CliRun text = w.ls5({"stream", "--port", w.port, "--count", "2", "--format", "text"});
  ASSERT_EQ(text.exit_code, cli::exit_ok) << text.err;
  EXPECT_EQ(count_of(text.out, "  2.1124 mm  code 21124"), 2U) << text.out;

  CliRun replay = run_cli(w.dir, {"replay", capture, "--full-speed", "--format", "jsonl"});
  ASSERT_EQ(replay.exit_code, cli::exit_ok) << replay.err;
  EXPECT_EQ(replay.out, jsonl.out);
}

// docs/conformance.md L67. Table 9.1 note 1: W, FL, ON, OF, FX, SB and DF may go to
// address 0; note 2: "No response in the case of a broadcast request". Commands that
// need an answer are refused at address 0 with the reason.
TEST(Ls5Cli, BroadcastReachesTheSensorForCommandsWithoutReplyL67) {
  Workspace w("broadcast");
  Child sim(sim_arguments(w));
  ASSERT_TRUE(contains(sim.read_line(), "ready:"));
  CliRun set = w.ls5({"set", "--port", w.port, "--address", "0", "median-points=7"});
  ASSERT_EQ(set.exit_code, cli::exit_ok) << set.err;
  EXPECT_EQ(w.ls5({"get", "--port", w.port, "median-points"}).out, "median-points=7\n");
  for (const char* command : {"off", "on", "save", "defaults"}) {
    CliRun run = w.ls5({command, "--port", w.port, "--address", "0"});
    EXPECT_EQ(run.exit_code, cli::exit_ok) << command << ": " << run.err;
  }
  EXPECT_EQ(w.ls5({"get", "--port", w.port, "median-points"}).out, "median-points=5\n") << "DF reached it";
  CliRun latch = w.ls5({"latch", "--port", w.port, "--address", "0"});
  EXPECT_EQ(latch.exit_code, cli::exit_ok) << latch.err;
  CliRun read_back = w.ls5({"latch", "--port", w.port, "--address", "0", "--read-only"});
  EXPECT_EQ(read_back.exit_code, cli::exit_usage) << read_back.out;
  EXPECT_TRUE(contains(read_back.err, "broadcast")) << read_back.err;
  for (const char* command : {"info", "measure", "get", "stream"}) {
    CliRun refused = w.ls5({command, "--port", w.port, "--address", "0"});
    EXPECT_EQ(refused.exit_code, cli::exit_usage) << command;
    EXPECT_TRUE(contains(refused.err, "broadcast")) << command << ": " << refused.err;
  }
}
