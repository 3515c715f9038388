// End to end over real ptys: every `rangekit uls` subcommand against
// `rangekit sim uls`, a bus of 8 units, config save/diff/load, and the driver's
// stream surviving the emulator being killed and restarted on the same path.
#include <gtest/gtest.h>
#include "build_paths.hpp"
#include "child_process.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "rangekit/core/serial_port.hpp"
#include "rangekit/sim/pty.hpp"
#include "rangekit/uls/driver.hpp"
#include "uls_driver/scripted_device.hpp"

namespace rangekit::uls {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

// A `rangekit sim uls` child process; waits for its "ready" line instead of sleeping.
class Emulator {
 public:
  explicit Emulator(const std::string& arguments) {
    int fds[2];
    EXPECT_EQ(::pipe(fds), 0);
    pid_ = rangekit::test::fork_child();
    if (pid_ == 0) {
      ::dup2(fds[1], STDOUT_FILENO);
      ::close(fds[0]);
      const std::string command = "exec " + std::string(rangekit::test::cli_path()) + " sim uls " + arguments;
      ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(fds[1]);
    out_ = fds[0];
    char c = 0;
    while (::read(out_, &c, 1) == 1 && c != '\n') ready_.push_back(c);
    EXPECT_NE(ready_.find("ready"), std::string::npos) << ready_;
  }
  ~Emulator() { stop(); }
  Emulator(const Emulator&) = delete;
  Emulator& operator=(const Emulator&) = delete;
  void stop() {
    if (pid_ <= 0) return;
    rangekit::test::end_child(pid_);
    ::close(out_);
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  std::string ready_;
};

struct CliRun {
  int code = -1;
  std::string out;  // stdout and stderr
};

CliRun cli(const std::string& arguments) {
  const std::string command = std::string(rangekit::test::cli_path()) + " " + arguments + " 2>&1";
  std::FILE* pipe = ::popen(command.c_str(), "r");
  CliRun run;
  if (pipe == nullptr) return run;
  std::array<char, 512> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) run.out += buffer.data();
  const int status = ::pclose(pipe);
  run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

fs::path scratch(const std::string& name) {
  const auto dir = fs::temp_directory_path() / ("rangekit-ulshost-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(UlsHostPty, EverySubcommandEndToEnd) {
  const auto dir = scratch("cli");
  const std::string port = (dir / "cfg").string();
  Emulator emulator("--port " + (dir / "uls").string() + " --config-port " + port + " --state " + dir.string());
  const std::string on = " --port " + port;

  CliRun run = cli("uls info" + on);
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("version=ULS"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("status=ready"), std::string::npos) << run.out;

  run = cli("uls set" + on + " mode=binning PF=2500 bin-size=4-inches");
  EXPECT_EQ(run.code, 0) << run.out;
  run = cli("uls get" + on + " mode prf BS");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("mode=binning  # MM=2"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("PF=2000,2500,2000"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("bin-size=4-inches  # BS=2"), std::string::npos) << run.out;

  // Refused locally, naming the range; nothing is sent (mode stays binning).
  run = cli("uls set" + on + " mode=averaging prf=6000");
  EXPECT_EQ(run.code, 2) << run.out;
  EXPECT_NE(run.out.find("10..5000"), std::string::npos) << run.out;
  EXPECT_NE(cli("uls get" + on + " mode").out.find("mode=binning"), std::string::npos);

  // Get with no names prints every readable setting.
  run = cli("uls get" + on);
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("trip-timeout-s=360  # TT=107AC0 (1080000 pulses)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("address=unassigned"), std::string::npos) << run.out;

  ASSERT_EQ(cli("uls set" + on + " mode=averaging").code, 0);
  run = cli("uls measure" + on + " --count 2");
  EXPECT_EQ(run.code, 0) << run.out;
  // Default scene: a wall at 50 m, within the ±4 cm of §9.
  EXPECT_EQ(count_of(run.out, "averaging distance_m="), 2U) << run.out;
  for (auto at = run.out.find("distance_m="); at != std::string::npos; at = run.out.find("distance_m=", at + 1))
    EXPECT_NEAR(std::stod(run.out.substr(at + 11, 8)), 50.0, 0.04) << run.out;

  // docs/conformance.md U77: measure left the unit measuring (BM starts it, §2), so GO answers
  // 31 "Instrument Is Already Measuring" (§10): start succeeds from any state and says so, as
  // stop does on a stopped unit (ST answers 86, U43), in the words the LS5 says them.
  run = cli("uls start" + on);
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_EQ(run.out, "measuring (it already was)\n");
  run = cli("uls stop" + on);
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_EQ(run.out, "stopped\n");
  run = cli("uls stop" + on);
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_EQ(run.out, "stopped (it was not measuring)\n");
  run = cli("uls start" + on);
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_EQ(run.out, "measuring\n");
  // A measuring unit refuses settings (§10 error 31, U24): set stops it, sets, reads back and
  // starts it again, so the next one finds it as the user left it.
  run = cli("uls set" + on + " power=low");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("the unit was measuring: stopped for the settings and started again"), std::string::npos)
      << run.out;
  run = cli("uls info" + on);
  EXPECT_NE(run.out.find("laser_firing=true"), std::string::npos) << run.out;
  EXPECT_EQ(cli("uls stop" + on).code, 0);

  run = cli("uls stream" + on + " --count 3 --format jsonl --quiet");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_EQ(count_of(run.out, "\"distance_m\":"), 3U) << run.out;
  run = cli("uls stream" + on + " --count 2 --format csv --mode polled --quiet");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("distance_m"), std::string::npos) << run.out;

  EXPECT_EQ(cli("uls save" + on).code, 0);
  // docs/conformance.md U65: §8 has no reset command; reset writes the factory values.
  run = cli("uls reset" + on);
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(cli("uls get" + on + " prf").out.find("prf-hz=2000,2000,2000"), std::string::npos);

  // No reply (wrong baud): exit 5 with a hint; a port that does not exist: exit 4; bad address: 2.
  run = cli("uls info" + on + " --baud 9600 --timeout 200");
  EXPECT_EQ(run.code, 5) << run.out;
  EXPECT_NE(run.out.find("baud"), std::string::npos) << run.out;
  EXPECT_EQ(cli("uls info --port " + (dir / "nothing").string()).code, 4);
  EXPECT_EQ(cli("uls info" + on + " --address '!'").code, 2);
  EXPECT_EQ(cli("uls get" + on + " nonsense").code, 2);
  EXPECT_EQ(cli("uls set --help").code, 0);
  emulator.stop();
  fs::remove_all(dir);
}

TEST(UlsHostPty, ConfigSaveChangeDiffLoad) {
  const auto dir = scratch("config");
  const std::string port = (dir / "cfg").string();
  Emulator emulator("--config-port " + port);
  const std::string on = " --port " + port;
  const std::string file = (dir / "unit.toml").string();

  CliRun run = cli("uls config save" + on + " " + file);
  ASSERT_EQ(run.code, 0) << run.out;
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("mode = \"averaging\"  # MM"), std::string::npos) << text;
  EXPECT_NE(text.find("prf-hz = [2000, 2000, 2000]  # PF"), std::string::npos) << text;

  // docs/conformance.md U64: readable distances are metres; BR and UA stay out of the file.
  EXPECT_EQ(text.find("baud"), std::string::npos) << text;
  EXPECT_EQ(text.find("address"), std::string::npos) << text;
  ASSERT_EQ(cli("uls set" + on + " prf=1000,1000,1000 short-gate=5 ppm=2000,2000 averaging-weight=1500").code, 0);
  run = cli("uls config diff" + on + " " + file);
  EXPECT_EQ(run.code, 1) << run.out;
  EXPECT_NE(run.out.find("prf-hz: file=2000,2000,2000 device=1000,1000,1000"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("short-gate-m: file=0 device=5"), std::string::npos) << run.out;

  // Loading AW 992 and PPM 1024 back needs the order rule (49: PPM must exceed AW).
  run = cli("uls config load" + on + " " + file);
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("0 differ"), std::string::npos) << run.out;
  run = cli("uls config diff" + on + " " + file);
  EXPECT_EQ(run.code, 0) << run.out;

  // A bad file names the line and the key.
  std::ofstream(dir / "bad.toml") << "[settings]\nmode = \"sideways\"\n";
  run = cli("uls config load" + on + " " + (dir / "bad.toml").string());
  EXPECT_NE(run.code, 0);
  EXPECT_NE(run.out.find("bad.toml:2: 'mode'"), std::string::npos) << run.out;
  emulator.stop();
  fs::remove_all(dir);
}

// docs/conformance.md U76: readable distances are metres whatever the unit's MU (U64); §9 "1700 m
// or 5577 ft" at its 0.01 ft resolution is 5577.43 ft, which the unit takes and reports back.
TEST(UlsHostPty, U76_MetreLimitsOnAUnitInFeet) {
  const auto dir = scratch("feet");
  const std::string port = (dir / "cfg").string();
  Emulator emulator("--config-port " + port);
  const std::string on = " --port " + port;
  const std::string file = (dir / "feet.toml").string();

  CliRun run = cli("uls set" + on + " units=ft short-gate=1700");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("SG=5577.43 OK"), std::string::npos) << run.out;
  run = cli("uls set" + on + " long-gate=5577.43ft offset=-1700 range-20ma=1700 TP=5577.43");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("LG=5577.43 OK"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("OF=-5577.43 OK"), std::string::npos) << run.out;
  run = cli("uls get" + on + " SG LG OF AH TP");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_EQ(count_of(run.out, "=5577.43"), 4U) << run.out;
  EXPECT_EQ(count_of(run.out, "=-5577.43"), 1U) << run.out;
  // One step beyond is refused locally, naming the limit in the unit's feet.
  run = cli("uls set" + on + " long-gate=1700.01");
  EXPECT_EQ(run.code, 2) << run.out;
  // A config saved from the unit in feet loads back with nothing differing.
  ASSERT_EQ(cli("uls config save" + on + " " + file).code, 0);
  run = cli("uls config diff" + on + " " + file);
  EXPECT_EQ(run.code, 0) << run.out;
  run = cli("uls config load" + on + " " + file);
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("0 differ"), std::string::npos) << run.out;
  // In metres the same limits read 1700.000.
  ASSERT_EQ(cli("uls set" + on + " units=m").code, 0);
  run = cli("uls get" + on + " SG LG OF");
  EXPECT_EQ(count_of(run.out, "=1700.000"), 2U) << run.out;
  EXPECT_EQ(count_of(run.out, "=-1700.000"), 1U) << run.out;
  emulator.stop();
  fs::remove_all(dir);
}

TEST(UlsHostPty, BusOfEightUnitsScanAssignPoll) {
  const auto dir = scratch("bus");
  const std::string bus = (dir / "rs485").string();
  Emulator emulator("--bus " + bus +
                    " --address A --address B --address C --address D --address E --address F "
                    "--address G --address H");
  const std::string on = " --port " + bus;

  // A scan shows how far it is (--progress: as on a terminal) and waits 150 ms at a silent
  // address, as docs/host-uls.md says, unless --timeout is given.
  CliRun run = cli("uls bus scan" + on + " --units ABCDEFGHIJz --progress");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("8 address(es) answered of 11 asked (150 ms at each silent one)"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("\rasked 1 of 11, 1 answered"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("\rasked 11 of 11, 8 answered"), std::string::npos) << run.out;
  run = cli("uls bus scan" + on + " --units Az --timeout 300");
  EXPECT_NE(run.out.find("1 address(es) answered of 2 asked (300 ms at each silent one)"), std::string::npos)
      << run.out;
  EXPECT_EQ(run.out.find("\rasked"), std::string::npos) << run.out;  // stderr is no terminal here

  run = cli("uls bus assign" + on + " --from C --to D");
  EXPECT_EQ(run.code, 2) << run.out;
  EXPECT_NE(run.out.find("already in use"), std::string::npos) << run.out;
  run = cli("uls bus assign" + on + " --from C --to z");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_EQ(cli("uls get" + on + " --address z mode").code, 0);
  EXPECT_EQ(cli("uls get" + on + " --address C mode --timeout 200").code, 5);

  run = cli("uls bus poll" + on + " --units ABDEFGHz --measure --rounds 2 --timeout 3000");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_EQ(count_of(run.out, "averaging address="), 16U) << run.out;

  // The poll's BM started the units (§2 Autostart), and a measuring unit refuses settings and UA
  // (error 31, U24): set stops it, sets, reads back and starts it again, and so does assign.
  run = cli("uls set" + on + " --address A mode=binning");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("the unit was measuring: stopped for the settings and started again"), std::string::npos)
      << run.out;
  EXPECT_NE(cli("uls get" + on + " --address A mode").out.find("mode=binning"), std::string::npos);
  run = cli("uls bus assign" + on + " --from A --to y");
  EXPECT_EQ(run.code, 0) << run.out;
  run = cli("uls info" + on + " --address y");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("laser_firing=true"), std::string::npos) << run.out;  // measuring again, at y
  // docs/conformance.md U66: a collision at an address is reported as a duplicate.
  // A raw UA set makes two units 'B' (what assign refuses); a scan reports the collision. Stopped
  // first: a set would start it again at 'B', where the two collide.
  ASSERT_EQ(cli("uls stop" + on + " --address y").code, 0);
  run = cli("uls set" + on + " --address y UA=B");
  ASSERT_EQ(run.code, 0) << run.out;
  run = cli("uls bus scan" + on + " --units Bz");
  EXPECT_NE(run.out.find("DUPLICATE"), std::string::npos) << run.out;
  emulator.stop();
  fs::remove_all(dir);
}

// U87 end to end: a ground at 20 m and a car that passes under the unit for 1 s every 4.5 s
// (§3 Look Down Mode: "ON is displayed when the system is tripped by presence detected").
// With TB on each edge is one line (§8: "$XXXX output at the start of presence detected", "$0
// output at the start of no presence detected"), and `uls stream` gives one sample per line,
// also after the 3.5 s of silence between two cars.
TEST(UlsHostPty, U87_LookDownStreamGivesOneSamplePerEdge) {
  const auto dir = scratch("lookdown");
  const std::string port = (dir / "cfg").string();
  {
    std::ofstream scene(dir / "scene.toml");
    scene << "[[targets]]\nname = \"ground\"\ndistance_m = 20\n\n"
             "[[targets]]\nname = \"car\"\npath = [[0, 30], [1.5, 30], [1.501, 10], [2.5, 10], [2.501, 30], "
             "[4.5, 30]]\nrepeat = true\n";
  }
  Emulator emulator("--config-port " + port + " --scene " + (dir / "scene.toml").string());
  const std::string on = " --port " + port;
  ASSERT_EQ(cli("uls set" + on + " mode=look-down TB=1").code, 0);
  const CliRun run = cli("uls stream" + on + " --count 3 --format jsonl");
  ASSERT_EQ(run.code, 0) << run.out;
  std::vector<std::string> samples;
  std::istringstream lines(run.out);
  for (std::string line; std::getline(lines, line);)
    if (line.find("\"kind\":\"look-down\"") != std::string::npos) samples.push_back(line);
  ASSERT_EQ(samples.size(), 3U) << run.out;
  // Edges alternate; a repeated state would be the last edge reported again.
  for (std::size_t i = 1; i < samples.size(); ++i) {
    const bool present = samples[i].find("\"presence\":true") != std::string::npos;
    const bool was_present = samples[i - 1].find("\"presence\":true") != std::string::npos;
    EXPECT_NE(present, was_present) << run.out;
  }
  fs::remove_all(dir);
}

// U90, U91, U92: what `rangekit uls` prints carries the §10 texts and the units.
TEST(UlsHostPty, U90_U92_OutputNamesErrorsAndUnits) {
  const auto dir = scratch("wording");
  const std::string port = (dir / "cfg").string();
  {
    // Far beyond the §9 maximum range: no pulse returns, §10 "4 Lock Not Found | Target Not Found".
    std::ofstream scene(dir / "far.toml");
    scene << "[[targets]]\ndistance_m = 4000\n";
  }
  Emulator emulator("--config-port " + port + " --scene " + (dir / "far.toml").string());
  const std::string on = " --port " + port;
  CliRun run = cli("uls measure" + on);
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("error 4: Lock Not Found (display: Target Not Found)"), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("error=4"), std::string::npos) << run.out;
  run = cli("uls stream" + on + " --count 1");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("uls  error 4: Lock Not Found (display: Target Not Found)"), std::string::npos) << run.out;

  // §8 DM 2 "Both": range and pulse width; §9 "yyyyyyy = pulse width (pico seconds)" (U8).
  {
    std::ofstream scene(dir / "near.toml");
    scene << "[[targets]]\ndistance_m = 50\npulse_width_ns = 25\n";
  }
  emulator.stop();
  Emulator near("--config-port " + port + " --scene " + (dir / "near.toml").string());
  run = cli("uls measure" + on);
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("pulse_width_ns=25.000"), std::string::npos) << run.out;
  run = cli("uls stream" + on + " --count 1");
  EXPECT_NE(run.out.find("pw 25.000 ns"), std::string::npos) << run.out;
  // The same name as `measure`, the same unit as the text.
  run = cli("uls stream" + on + " --count 1 --format jsonl");
  EXPECT_NE(run.out.find("\"pulse_width_ns\":25.000}"), std::string::npos) << run.out;

  // U91: §9 baud choices; 28800 is none of them, and a lone value is not a port.
  run = cli("uls set" + on + " baud=0,28800");
  EXPECT_EQ(run.code, 2) << run.out;
  EXPECT_NE(run.out.find("1200, 2400, 4800, 9600, 14400, 19200, 38400, 57600, 115200, 230400"), std::string::npos)
      << run.out;
  run = cli("uls set" + on + " baud=28800");
  EXPECT_EQ(run.code, 2) << run.out;
  EXPECT_NE(run.out.find("the port and the baud"), std::string::npos) << run.out;
  fs::remove_all(dir);
}

// U93: docs/host-uls.md exit codes, "5 no reply (... `bus poll` when a unit stayed silent); 6 a
// device error". A scripted bus on a pty: unit 'A' answers US and the gets `measure` needs but
// never BM (silent), unit 'B' answers BM with §10 error 7, Measurement Read Error.
TEST(UlsHostPty, U93_BusPollExitsFiveWhenAUnitStaysSilentOnBm) {
  auto pty = PseudoTerminal::open();
  ASSERT_TRUE(pty) << pty.error().message;
  ASSERT_TRUE((*pty)->hold_slave_open());  // the CLI opening and closing it is no hang-up
  const std::string path = (*pty)->slave_path();
  testing::ScriptedDevice bus(std::move(*pty), [](const std::string& request) -> std::string {
    if (request.size() < 3 || request[0] != '#') return "";
    const std::string unit = request.substr(0, 2);
    const std::string mnemonic = request.substr(2);
    if (mnemonic == "US") return unit + "US,7\r";
    if (mnemonic == "MM") return unit + "MM,1\r";
    if (mnemonic == "DM") return unit + "DM,2\r";
    if (mnemonic == "MU") return unit + "MU,1\r";
    if (mnemonic == "TB") return unit + "TB,0\r";
    if (mnemonic == "BM" && unit == "#B") return "#BER,7\r";
    return "";
  });
  CliRun run = cli("uls bus poll --port " + path + " --units B --measure");
  EXPECT_EQ(run.code, 6) << run.out;
  EXPECT_NE(run.out.find("device error 7"), std::string::npos) << run.out;
  run = cli("uls bus poll --port " + path + " --units AB --measure");
  EXPECT_EQ(run.code, 5) << run.out;
  EXPECT_NE(run.out.find("no reply to $BM"), std::string::npos) << run.out;
  run = cli("uls bus poll --port " + path + " --units A");  // US alone: A answers
  EXPECT_EQ(run.code, 0) << run.out;
}

std::vector<StreamItem> take_until(SampleSource& source,
                                   const std::function<bool(const std::vector<StreamItem>&)>& done) {
  std::vector<StreamItem> items;
  const auto until = std::chrono::steady_clock::now() + 20s;
  while (!done(items) && std::chrono::steady_clock::now() < until) {
    if (auto item = source.next(100ms)) items.push_back(std::move(*item));
  }
  return items;
}

bool has_event(const std::vector<StreamItem>& items, StreamEventKind kind) {
  for (const auto& item : items)
    if (const auto* event = std::get_if<StreamEvent>(&item); event != nullptr && event->kind == kind) return true;
  return false;
}

std::size_t samples_after(const std::vector<StreamItem>& items, StreamEventKind kind) {
  std::size_t count = 0;
  bool seen = false;
  for (const auto& item : items) {
    if (const auto* event = std::get_if<StreamEvent>(&item); event != nullptr && event->kind == kind) seen = true;
    if (seen && std::holds_alternative<Sample>(item)) ++count;
  }
  return count;
}

TEST(UlsHostPty, StreamReconnectsWhenTheEmulatorComesBack) {
  // docs/conformance.md U63
  const auto dir = scratch("reconnect");
  const std::string port = (dir / "cfg").string();
  auto emulator = std::make_unique<Emulator>("--config-port " + port);
  ReopenFunction reopen = [port]() -> Result<TransportPtr> {
    auto opened = SerialPort::open(port, SerialSettings{});
    if (!opened) return opened.error();
    return TransportPtr(std::move(*opened));
  };
  auto first = reopen();
  ASSERT_TRUE(first) << first.error().message;
  DriverOptions options;
  options.reconnect_interval = 100ms;
  Driver driver(std::move(*first), options, reopen);
  auto stream = driver.start_stream();
  ASSERT_TRUE(stream) << stream.error().message;
  auto items =
      take_until(**stream, [](const auto& got) { return samples_after(got, StreamEventKind::connected) >= 1; });
  ASSERT_GE(samples_after(items, StreamEventKind::connected), 1U);

  emulator->stop();  // the pty and its symlink vanish: the cable is out
  items = take_until(**stream, [](const auto& got) { return has_event(got, StreamEventKind::disconnected); });
  ASSERT_TRUE(has_event(items, StreamEventKind::disconnected));
  emulator = std::make_unique<Emulator>("--config-port " + port);  // power back, same path
  items = take_until(**stream, [](const auto& got) { return samples_after(got, StreamEventKind::reconnected) >= 2; });
  EXPECT_TRUE(has_event(items, StreamEventKind::reconnected));
  EXPECT_GE(samples_after(items, StreamEventKind::reconnected), 2U);
  driver.stop_stream();
  emulator->stop();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rangekit::uls
