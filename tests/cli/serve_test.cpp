// `rangekit serve --check` and `--config` (docs/service.md).
#include <gtest/gtest.h>
#include <signal.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "child_process.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/sim/control_socket.hpp"
#include "web/http_client.hpp"

namespace {

using ls5_driver_test::Child;
using ls5_driver_test::run_cli;
using ls5_driver_test::TempDir;

std::string write_site(const TempDir& dir, const std::string& text) {
  const auto path = (dir.path / "site.toml").string();
  std::ofstream(path) << text;
  return path;
}

TEST(Serve, CheckDescribesAGoodFileAndRefusesABadOneWithItsLine) {
  TempDir dir;
  const auto good = write_site(dir,
                               "[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\naddress = \"A\"\n"
                               "[[sensor]]\nname = \"b\"\nfamily = \"uls\"\nport = \"/dev/x\"\naddress = \"B\"\n");
  auto run = run_cli(dir.path, {"serve", "--check", good});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("2 sensors on 1 ports"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("/dev/x (115200 8N1, RS-485 bus): a b"), std::string::npos) << run.out;

  const auto bad = write_site(dir, "[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\nbuad = 9600\n");
  run = run_cli(dir.path, {"serve", "--check", bad});
  EXPECT_EQ(run.exit_code, 3);
  EXPECT_NE(run.err.find("site.toml:5: unknown key 'buad'"), std::string::npos) << run.err;

  run = run_cli(dir.path, {"serve", "--check", (dir.path / "missing.toml").string()});
  EXPECT_EQ(run.exit_code, 4);
  EXPECT_NE(run.err.find("cannot read site file"), std::string::npos) << run.err;
  EXPECT_EQ(run_cli(dir.path, {"serve"}).exit_code, 2);
}

std::size_t count_of(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

// A sensor's change of state is said once, with its reason; piped (a journal), nothing is
// said again each second, and the table comes once, at the end.
TEST(Serve, AChangeOfStateIsSaidOnceWithItsReasonAndNotEverySecond) {
  TempDir dir;
  const auto port = (dir.path / "ls5").string();
  const auto missing = (dir.path / "unplugged").string();
  Child sim({"sim", "ls5", "--port", port});
  ASSERT_NE(sim.read_line().find("ready"), std::string::npos);
  const auto site =
      write_site(dir, "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"" + port +
                          "\"\n[[sensor]]\nname = \"ghost\"\nfamily = \"ls5\"\nport = \"" + missing + "\"\n");
  const auto run = run_cli(dir.path, {"serve", "--config", site, "--listen", "127.0.0.1:0", "--duration", "3.5"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(count_of(run.out, " ghost: disconnected: cannot open serial port " + missing + ": "), 1U) << run.out;
  EXPECT_EQ(count_of(run.out, " belt: streaming\n"), 1U) << run.out;
  // The table's lines ("ghost            ls5 disconnected ...") once each: the summary at the end.
  EXPECT_EQ(count_of(run.out, "\nghost "), 1U) << run.out;
  EXPECT_EQ(run.out.find("\x1b["), std::string::npos) << "no cursor movement into a pipe";
}

// --table draws the table as a terminal shows it: redrawn in place, the changes above it.
TEST(Serve, TheTableIsRedrawnInPlaceOnATerminal) {
  TempDir dir;
  const auto port = (dir.path / "ls5").string();
  Child sim({"sim", "ls5", "--port", port});
  ASSERT_NE(sim.read_line().find("ready"), std::string::npos);
  const auto site = write_site(dir, "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"" + port + "\"\n");
  const auto run =
      run_cli(dir.path, {"serve", "--config", site, "--listen", "127.0.0.1:0", "--duration", "2.5", "--table"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  // Up one line (the table is one sensor) and cleared, then drawn again.
  EXPECT_GE(count_of(run.out, "\x1b[1A\x1b[J"), 1U) << run.out;
  EXPECT_GE(count_of(run.out, "\nbelt "), 2U) << run.out;
}

TEST(Serve, ServesTheSiteForItsDurationAndLeavesTheSensorAsFound) {
  TempDir dir;
  const auto port = (dir.path / "ls5").string();
  Child sim({"sim", "ls5", "--port", port});
  ASSERT_NE(sim.read_line().find("ready"), std::string::npos);
  const auto site = write_site(dir, "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"" + port + "\"\n");
  const auto run = run_cli(dir.path, {"serve", "--config", site, "--duration", "1.5"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  // The last summary line: the sensor streamed and its records were counted.
  const auto last = run.out.rfind("belt ");
  ASSERT_NE(last, std::string::npos) << run.out;
  EXPECT_NE(run.out.find("ls5", last), std::string::npos);
  EXPECT_EQ(run.out.find("records 0 ", last), std::string::npos) << run.out;
  // The port is free again: a one-shot command gets the sensor's identity.
  const auto info = run_cli(dir.path, {"ls5", "info", "--port", port});
  EXPECT_EQ(info.exit_code, 0) << info.err;
}

// Reads the service's stdout up to its "API on http://HOST:PORT/" line; the port, 0 if none.
std::uint16_t api_port(Child& service, std::string* before = nullptr) {
  for (std::string line = service.read_line(); !line.empty(); line = service.read_line()) {
    if (before != nullptr) *before += line;
    const auto at = line.find("API on http://127.0.0.1:");
    if (at != std::string::npos) return static_cast<std::uint16_t>(std::stoi(line.substr(at + 24)));
  }
  return 0;
}

// The processes whose command line names `text` (the demo's emulators name its directory).
std::set<pid_t> processes_naming(const std::string& text) {
  std::set<pid_t> found;
  for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
    const std::string name = entry.path().filename();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string command_line = ls5_driver_test::read_file(entry.path() / "cmdline");
    for (char& c : command_line) c = c == '\0' ? ' ' : c;
    if (command_line.find(text) != std::string::npos && command_line.find(" sim ") != std::string::npos) {
      found.insert(static_cast<pid_t>(std::stoi(name)));
    }
  }
  return found;
}

nlohmann::json emulator_outputs(const std::string& control) {
  auto client = rangekit::ControlClient::connect(control);
  if (!client) return {};
  auto reply = client->request({{"cmd", "outputs"}});
  return reply ? *reply : nlohmann::json{};
}

// The emulators' folder from the demo's first lines ("starting the emulators on
// pseudo-terminals in DIR"); empty when they do not name one.
std::string demo_folder(const std::string& head) {
  const auto at = head.find(" in /");
  if (at == std::string::npos) return {};
  return head.substr(at + 4, head.find('\n', at) - at - 4);
}

// "`rangekit serve --demo`: the embedded default. It starts the two emulators
// plus an RS-485 bus of four ULS units as child processes, with moving targets (one ULS in binning
// with two targets, one in look-down with a target that passes), and serves them."
// The duration is long and the test ends the service with SIGTERM once it has seen everything,
// so a loaded machine cannot end the run before the checks (`--duration` is covered above).
TEST(ServeDemo, ServesSevenLiveSensorsAndStopsItsEmulators) {
  Child service({"serve", "--demo", "--duration", "120", "--listen", "127.0.0.1:0"});
  std::string head;
  const std::uint16_t port = api_port(service, &head);
  ASSERT_NE(port, 0) << head;  // port 0 asked: the printed line names the port it got
  const std::string dir = demo_folder(head);
  ASSERT_FALSE(dir.empty()) << head;
  const std::set<pid_t> emulators = processes_naming(dir);
  EXPECT_EQ(emulators.size(), 3u) << head;  // the LS5, the ULS, the bus of four

  web_test::EventReader events(port, "/api/events");
  std::set<std::string> heard;
  bool two_targets = false;  // bay-A: binning, a crate in front of a wall
  bool presence = false;     // bay-B: look down, a box passing over the floor
  const bool all = events.read_until([&](const web_test::Event& event) {
    if (event.type != "sample") return false;
    const auto item = nlohmann::json::parse(event.data);
    const std::string sensor = item["sensor"];
    heard.insert(sensor);
    const auto& data = item["data"];
    if (sensor == "bay-A" && data.value("kind", "") == "binning" && data["targets"].size() == 2) two_targets = true;
    if (sensor == "bay-B" && data.value("kind", "") == "look-down" && data["presence"].is_boolean()) presence = true;
    return heard.size() == 7 && two_targets && presence;
  });
  EXPECT_TRUE(all) << heard.size() << " sensors heard; two targets " << two_targets << ", presence " << presence;
  events.close();

  const auto list = web_test::http(port, "GET", "/api/sensors");
  ASSERT_EQ(list.status, 200) << list.body;
  const auto sensors = nlohmann::json::parse(list.body)["sensors"];
  std::set<std::string> names;
  for (const auto& sensor : sensors) {
    names.insert(sensor["name"].get<std::string>());
    EXPECT_TRUE(sensor["connected"].get<bool>()) << sensor["name"];
    EXPECT_TRUE(sensor["streaming"].get<bool>()) << sensor["name"];
    EXPECT_GT(sensor["health"]["records"].get<int>(), 0) << sensor["name"];
  }
  EXPECT_EQ(names, (std::set<std::string>{"belt", "belt-udp", "silo", "bay-A", "bay-B", "bay-C", "bay-D"}));

  service.terminate();
  while (!service.read_line().empty()) {
  }
  EXPECT_EQ(service.wait(), 130);  // ended by a signal, cleanly
  for (const pid_t emulator : emulators) {
    EXPECT_TRUE(::kill(emulator, 0) != 0 && errno == ESRCH) << "emulator " << emulator << " still there";
  }
  EXPECT_FALSE(std::filesystem::exists(dir)) << dir;
}

// A service killed outright (SIGKILL, a crash) takes its emulators along: each has the
// kernel's parent-death signal, so none is left holding a pseudo-terminal (docs/security.md).
TEST(ServeDemo, AKilledServiceTakesItsEmulatorsAlong) {
  const rangekit::test::OrphanReaper reaper;  // the orphaned emulators come here, to be waited for
  Child service({"serve", "--demo", "--duration", "120", "--listen", "127.0.0.1:0"});
  std::string head;
  ASSERT_NE(api_port(service, &head), 0) << head;
  const std::string dir = demo_folder(head);
  ASSERT_FALSE(dir.empty()) << head;
  const std::set<pid_t> emulators = processes_naming(dir);
  ASSERT_EQ(emulators.size(), 3u) << head;
  service.kill_hard();
  for (const pid_t emulator : emulators) {
    EXPECT_TRUE(rangekit::test::reaped_within(emulator, std::chrono::seconds(10)))
        << "emulator " << emulator << " outlived the service";
  }
}

// Reads the service's summary lines until one says it streams and has counted records.
bool streams_with_records(Child& service) {
  for (std::string line = service.read_line(); !line.empty(); line = service.read_line()) {
    if (line.find("streaming") != std::string::npos && line.find("records 0 ") == std::string::npos) return true;
  }
  return false;
}

// Reads the service's output to its end and gives its last "capture ..." line.
std::string last_capture_line(Child& service) {
  std::string capture_line;
  for (std::string line = service.read_line(); !line.empty(); line = service.read_line()) {
    if (line.rfind("capture ", 0) == 0) capture_line = line;
  }
  return capture_line;
}

// The service's "capture ...: N samples, 0 lost → FILE" line: the capture was committed and
// closed, it replays, and holds what the service said it wrote.
void expect_capture_whole(const TempDir& dir, const std::string& capture_line) {
  ASSERT_NE(capture_line.find(" samples, 0 lost → "), std::string::npos) << capture_line;
  std::string file = capture_line.substr(capture_line.find("→ ") + std::string("→ ").size());
  while (!file.empty() && (file.back() == '\n' || file.back() == '\r')) file.pop_back();
  const auto samples = std::stoul(capture_line.substr(capture_line.find(": ") + 2));
  EXPECT_GT(samples, 0u);
  const auto replay = run_cli(dir.path, {"replay", file, "--full-speed", "--format", "jsonl"});
  EXPECT_EQ(replay.exit_code, 0) << replay.err;
  std::istringstream lines(replay.out);
  unsigned long replayed = 0;
  for (std::string each; std::getline(lines, each);) replayed += each.find("\"device\":\"ls5\"") != std::string::npos;
  EXPECT_EQ(replayed, samples);
}

// SIGTERM closes the captures cleanly and releases the ports. U86: the stream the service
// started is ended (table 9.1 "SB: Stop the stream") before it exits.
TEST(Serve, U86_SigtermClosesTheCaptureReleasesThePortAndLeavesTheLs5NotStreaming) {
  TempDir dir;
  const auto port = (dir.path / "ls5").string();
  const auto control = (dir.path / "ls5.control").string();
  Child sim({"sim", "ls5", "--port", port, "--control", control});
  ASSERT_NE(sim.read_line().find("ready"), std::string::npos);
  const auto site =
      write_site(dir, "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"" + port + "\"\ncapture = true\n");
  Child service({"serve", "--config", site, "--listen", "127.0.0.1:0"});
  ASSERT_NE(api_port(service), 0);
  ASSERT_TRUE(streams_with_records(service));
  ASSERT_EQ(emulator_outputs(control).value("streaming", false), true);

  service.terminate();
  const std::string capture_line = last_capture_line(service);
  EXPECT_EQ(service.wait(), 130);
  EXPECT_EQ(emulator_outputs(control).value("streaming", true), false);
  const auto info = run_cli(dir.path, {"ls5", "info", "--port", port});
  EXPECT_EQ(info.exit_code, 0) << info.err;
  // The capture (capture = true, in captures/ beside the site file) was committed and closed:
  // it replays, and holds what the service said it wrote.
  expect_capture_whole(dir, capture_line);
}

// A SIGTERM while writes arrive: each write is answered or its connection closed (none hangs,
// none gets a 500), the process ends as it does when idle, and the capture holds every sample
// it said it wrote.
TEST(Serve, SigtermWhileWritesArriveEndsCleanlyWithTheCaptureWhole) {
  TempDir dir;
  const auto port = (dir.path / "ls5").string();
  Child sim({"sim", "ls5", "--port", port});
  ASSERT_NE(sim.read_line().find("ready"), std::string::npos);
  const auto site =
      write_site(dir, "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"" + port + "\"\ncapture = true\n");
  Child service({"serve", "--config", site, "--listen", "127.0.0.1:0"});
  const std::uint16_t api = api_port(service);
  ASSERT_NE(api, 0);
  // Writes begin once records arrive: on a slow (sanitizer) build the writes could otherwise
  // all be answered before the first record, leaving the capture nothing to check.
  ASSERT_TRUE(streams_with_records(service));
  std::atomic<bool> stopping{false};
  std::atomic<int> answered{0};
  std::atomic<int> closed{0};
  std::mutex mutex;
  std::vector<std::string> wrong;  // answers that are neither a status below 500 nor a close
  const auto writer = [&](const std::string& method, const std::string& target, const std::string& body) {
    while (!stopping) {
      const auto reply = web_test::http(api, method, target, body);
      if (reply.status == 0) {
        ++closed;
        continue;
      }
      ++answered;
      // 503: refused while stopping; 409/400: the sensor busy or not streaming any more.
      if (reply.status >= 500 && reply.status != 503) {
        std::lock_guard lock(mutex);
        wrong.push_back(std::to_string(reply.status) + " " + reply.body);
      }
    }
  };
  std::vector<std::thread> writers;
  writers.emplace_back(writer, "POST", "/api/sensors/belt/actions/single", "{}");
  writers.emplace_back(writer, "PATCH", "/api/sensors/belt/settings", R"({"median-points": 7})");
  writers.emplace_back(writer, "POST", "/api/sensors/belt/actions/single", "{}");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (answered < 6 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // polls a count, with a deadline
  }
  ASSERT_GE(answered.load(), 6) << "the writes were not being answered";
  service.terminate();
  const std::string capture_line = last_capture_line(service);
  EXPECT_EQ(service.wait(), 130);
  stopping = true;
  for (auto& thread : writers) thread.join();
  EXPECT_TRUE(wrong.empty()) << wrong.front();
  EXPECT_GT(closed.load(), 0) << "no write met the stopped service";
  expect_capture_whole(dir, capture_line);
}

}  // namespace
