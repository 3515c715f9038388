// The gateway service the .deb installs (docs/deploy.md): the systemd unit as systemd-analyze
// reads it, its ExecStartPre on the sample site file, its ExecStart run as systemd would run it
// (notify socket, watchdog, journal, state folder), and a service started before its sensor.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>
#include "build_paths.hpp"
#include "child_process.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cli/cli_run.hpp"
#include "ls5_driver/cli_process.hpp"

extern char** environ;

namespace {

using ls5_driver_test::Child;
using ls5_driver_test::read_file;
using ls5_driver_test::TempDir;
using Clock = std::chrono::steady_clock;

const std::string source_root = rangekit::test::source_dir();
const std::string packaged_binary = "/usr/bin/rangekit";
const std::string packaged_site = "/etc/rangekit/site.toml";

std::string unit_text() { return read_file(source_root + "/packaging/systemd/rangekit.service"); }

// The values of the unit's `KEY=` lines, in order.
std::vector<std::string> unit_values(const std::string& key) {
  std::vector<std::string> values;
  std::istringstream lines(unit_text());
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind(key + "=", 0) == 0) values.push_back(line.substr(key.size() + 1));
  }
  return values;
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  for (auto at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

// A command line of the unit as this build runs it: the packaged binary and site file replaced
// by this build's binary and `site`, split at spaces (the unit quotes nothing).
std::vector<std::string> command_of(const std::string& line, const std::string& site) {
  std::istringstream words(replaced(replaced(line, packaged_binary, rangekit::test::cli_path()), packaged_site, site));
  std::vector<std::string> argv;
  for (std::string word; words >> word;) argv.push_back(word);
  return argv;
}

// A process started with more environment, its stdout and stderr on one pipe, read line by
// line with a deadline; SIGTERM and a wait when the test ends first. `journal`: the pipe is
// named in JOURNAL_STREAM (its device and inode), as systemd names the journal's stream.
class Service {
 public:
  Service(const std::vector<std::string>& argv, const std::vector<std::string>& environment, bool journal) {
    int out[2];
    if (::pipe2(out, O_CLOEXEC) != 0) return;
    // Built before fork: the child only execs.
    std::vector<std::string> env_text = environment;
    if (journal) {
      struct stat info {};
      ::fstat(out[1], &info);
      env_text.push_back("JOURNAL_STREAM=" + std::to_string(info.st_dev) + ":" + std::to_string(info.st_ino));
    }
    for (char** entry = environ; *entry != nullptr; ++entry) env_text.emplace_back(*entry);
    std::vector<char*> env;
    for (auto& entry : env_text) env.push_back(entry.data());
    env.push_back(nullptr);
    std::vector<std::string> argv_text = argv;
    std::vector<char*> args;
    for (auto& word : argv_text) args.push_back(word.data());
    args.push_back(nullptr);
    pid_ = rangekit::test::fork_child();
    if (pid_ == 0) {
      ::dup2(out[1], STDOUT_FILENO);
      ::dup2(out[1], STDERR_FILENO);
      ::execve(args[0], args.data(), env.data());
      ::_exit(127);
    }
    ::close(out[1]);
    out_ = out[0];
  }
  ~Service() {
    if (pid_ > 0 && !status_) rangekit::test::end_child(pid_);
    if (out_ >= 0) ::close(out_);
  }
  Service(const Service&) = delete;
  Service& operator=(const Service&) = delete;

  [[nodiscard]] pid_t pid() const { return pid_; }
  [[nodiscard]] const std::string& output() const { return output_; }

  // The first whole line, from here on, that contains `part`; nothing when none came in `limit`.
  std::optional<std::string> line_with(const std::string& part, std::chrono::milliseconds limit) {
    const auto deadline = Clock::now() + limit;
    while (true) {
      for (auto end = pending_.find('\n'); end != std::string::npos; end = pending_.find('\n')) {
        std::string line = pending_.substr(0, end);
        pending_.erase(0, end + 1);
        if (line.find(part) != std::string::npos) return line;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
      if (left.count() <= 0) return std::nullopt;
      pollfd ready{out_, POLLIN, 0};
      if (::poll(&ready, 1, static_cast<int>(left.count())) <= 0) continue;
      char buffer[4096];
      const ssize_t got = ::read(out_, buffer, sizeof buffer);
      if (got <= 0) return std::nullopt;  // it ended
      pending_.append(buffer, static_cast<std::size_t>(got));
      output_.append(buffer, static_cast<std::size_t>(got));
    }
  }

  // Whether it is still running (not reaped).
  bool running() {
    if (status_) return false;
    if (auto status = rangekit::test::waited_within(pid_, std::chrono::milliseconds(0))) status_ = status;
    return !status_;
  }

  // SIGTERM, then its exit code once it ended (-1: killed by a signal or still running after 20 s).
  int terminate() {
    ::kill(pid_, SIGTERM);
    status_ = rangekit::test::waited_within(pid_, std::chrono::seconds(20));
    if (!status_) return -1;
    return WIFEXITED(*status_) ? WEXITSTATUS(*status_) : -1;
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  std::string pending_;
  std::string output_;
  std::optional<int> status_;
};

// What systemd listens on as NOTIFY_SOCKET: an AF_UNIX datagram socket at a path.
class NotifySocket {
 public:
  explicit NotifySocket(const std::filesystem::path& path) : path_(path.string()) {
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, path_.c_str(), sizeof address.sun_path - 1);
    bound_ = ::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
  }
  ~NotifySocket() { ::close(fd_); }
  NotifySocket(const NotifySocket&) = delete;
  NotifySocket& operator=(const NotifySocket&) = delete;
  [[nodiscard]] bool bound() const { return bound_; }
  [[nodiscard]] const std::string& path() const { return path_; }

  // The next message; nothing when none came in `limit`.
  std::optional<std::string> next(std::chrono::milliseconds limit) {
    pollfd ready{fd_, POLLIN, 0};
    if (::poll(&ready, 1, static_cast<int>(limit.count())) <= 0) return std::nullopt;
    char buffer[4096];
    const ssize_t got = ::recv(fd_, buffer, sizeof buffer, 0);
    if (got < 0) return std::nullopt;
    return std::string(buffer, static_cast<std::size_t>(got));
  }

  // Messages until one holds the line `state` ("WATCHDOG=1"); false when none did in `limit`.
  bool wait_for(const std::string& state, std::chrono::milliseconds limit, std::string& seen) {
    const auto deadline = Clock::now() + limit;
    while (Clock::now() < deadline) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
      const auto message = next(left);
      if (!message) return false;
      seen += *message + "\n--\n";
      if (("\n" + *message + "\n").find("\n" + state + "\n") != std::string::npos) return true;
    }
    return false;
  }

 private:
  std::string path_;
  int fd_ = -1;
  bool bound_ = false;
};

TEST(ServiceUnit, SystemdAnalyzeVerifiesTheUnitWithoutAWarning) {
  TempDir dir;
  const auto site = dir.path / "site.toml";
  std::filesystem::copy_file(source_root + "/packaging/site.toml", site);
  // verify needs ExecStart's binary to exist: this build's stands in for /usr/bin/rangekit.
  const std::string unit =
      replaced(replaced(unit_text(), packaged_binary, rangekit::test::cli_path()), packaged_site, site.string());
  ASSERT_NE(unit, unit_text()) << "the unit names neither " << packaged_binary << " nor " << packaged_site;
  const auto unit_file = dir.path / "rangekit.service";
  std::ofstream(unit_file) << unit;
  // A directive it cannot parse is only a warning, exit 0: any output fails the test. --man=no:
  // the man page of Documentation= is installed by the package, not here.
  const auto run = cli_test::run_shell("systemd-analyze verify --man=no " + unit_file.string() + " 2>&1");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.output, "") << "systemd-analyze said something about the unit";
}

// What docs/deploy.md promises of the unit, line for line.
TEST(ServiceUnit, HasTheTypeUserFoldersAndHardeningTheDeployPageDescribes) {
  const std::vector<std::pair<std::string, std::string>> expected{
      {"Type", "notify"},
      {"User", "rangekit"},
      {"SupplementaryGroups", "dialout"},
      {"StateDirectory", "rangekit"},
      {"ConfigurationDirectory", "rangekit"},
      {"Restart", "on-failure"},
      {"ProtectSystem", "strict"},
      {"ProtectHome", "yes"},
      {"PrivateTmp", "yes"},
      {"NoNewPrivileges", "yes"},
      {"DevicePolicy", "closed"},
      {"ExecStartPre", packaged_binary + " serve --check " + packaged_site},
      {"ExecStart", packaged_binary + " serve --config " + packaged_site},
  };
  for (const auto& [key, value] : expected) EXPECT_EQ(unit_values(key), std::vector<std::string>{value}) << key;
  const auto devices = unit_values("DeviceAllow");
  for (const std::string group : {"char-ttyUSB rw", "char-ttyACM rw", "char-ttyS rw", "char-pts rw"}) {
    EXPECT_NE(std::find(devices.begin(), devices.end(), group), devices.end()) << group;
  }
  ASSERT_EQ(unit_values("WatchdogSec").size(), 1U);
}

// The package's site file is what the technician starts from: ExecStartPre accepts it as
// shipped, and with every commented example turned on.
TEST(ServiceUnit, ExecStartPreAcceptsTheSampleSiteFileAndItsExamples) {
  const auto pre = unit_values("ExecStartPre");
  ASSERT_EQ(pre.size(), 1U);
  TempDir dir;
  const auto shipped = source_root + "/packaging/site.toml";
  auto quoted = [](const std::vector<std::string>& argv) {
    std::string line;
    for (const auto& word : argv) line += "'" + word + "' ";
    return line + "2>&1";
  };
  auto run = cli_test::run_shell(quoted(command_of(pre.front(), shipped)));
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(cli_test::contains(run.output, "1 sensors on 1 ports")) << run.output;

  // "# name = ..." and "# [[sensor]]" lines uncommented; prose comments stay comments.
  const std::regex example(R"(^# (\[|(?:name|family|port|address|broker|base_topic|listen) ))", std::regex::multiline);
  const auto all = dir.path / "site.toml";
  std::ofstream(all) << std::regex_replace(read_file(shipped), example, "$1");
  run = cli_test::run_shell(quoted(command_of(pre.front(), all.string())));
  EXPECT_EQ(run.exit_code, 0) << run.output << read_file(all);
  EXPECT_TRUE(cli_test::contains(run.output, "4 sensors on 3 ports")) << run.output;
  EXPECT_TRUE(cli_test::contains(run.output, "mqtt mqtt://")) << run.output;
  EXPECT_TRUE(cli_test::contains(run.output, "modbus ")) << run.output;
}

// ExecStart as systemd runs it: a notify socket, a watchdog of 300 ms, the journal as stdout and
// a state folder. READY=1 comes first, WATCHDOG=1 every half interval, STOPPING=1 at SIGTERM,
// whose exit code the unit counts as success; the journal gets lines without timestamps, and
// captures go to the state folder, nothing beside the (read only) site file.
TEST(ServiceUnit, ExecStartSaysReadyKeepsTheWatchdogAndSaysStopping) {
  const auto start = unit_values("ExecStart");
  ASSERT_EQ(start.size(), 1U);
  TempDir dir;
  std::filesystem::create_directories(dir.path / "etc");
  std::filesystem::create_directories(dir.path / "state");
  const auto site = (dir.path / "etc" / "site.toml").string();
  const auto absent = (dir.path / "absent").string();
  std::ofstream(site) << "[service]\nlisten = \"127.0.0.1:0\"\ncapture_dir = \"captures\"\n[[sensor]]\n"
                         "name = \"ghost\"\nfamily = \"ls5\"\ncapture = true\nport = \""
                      << absent << "\"\n";
  NotifySocket notify(dir.path / "notify");
  ASSERT_TRUE(notify.bound()) << std::strerror(errno);
  const std::vector<std::string> environment{"NOTIFY_SOCKET=" + notify.path(), "WATCHDOG_USEC=300000",
                                             "STATE_DIRECTORY=" + (dir.path / "state").string()};
  Service service(command_of(start.front(), site), environment, true);
  ASSERT_GT(service.pid(), 0);
  std::string seen;
  ASSERT_TRUE(notify.wait_for("READY=1", std::chrono::seconds(30), seen)) << seen << service.output();
  EXPECT_EQ(seen.find("WATCHDOG=1"), std::string::npos) << "a ping before READY=1: " << seen;
  EXPECT_NE(seen.find("STATUS=1 sensor: 1 disconnected"), std::string::npos) << seen;
  for (int ping = 0; ping < 3; ++ping) {
    ASSERT_TRUE(notify.wait_for("WATCHDOG=1", std::chrono::seconds(5), seen)) << ping << ": " << seen;
  }
  const auto said =
      service.line_with("ghost: disconnected: cannot open serial port " + absent, std::chrono::seconds(10));
  ASSERT_TRUE(said.has_value()) << service.output();
  EXPECT_EQ(said->rfind("ghost: ", 0), 0U) << "the journal stamps lines itself: " << *said;

  EXPECT_EQ(service.terminate(), std::stoi(unit_values("SuccessExitStatus").at(0))) << service.output();
  EXPECT_TRUE(notify.wait_for("STOPPING=1", std::chrono::seconds(1), seen)) << seen;
  std::vector<std::string> beside_site;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path / "etc")) {
    beside_site.push_back(entry.path().filename());
  }
  EXPECT_EQ(beside_site, std::vector<std::string>{"site.toml"});
  std::size_t captures = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path / "state" / "captures")) {
    captures += entry.path().extension() == ".sqlite" ? 1 : 0;
  }
  EXPECT_EQ(captures, 1U);
}

// Installed and enabled, the service starts at boot whether or not its adapter is plugged in:
// a missing port is said once, retried, and the sensor streams once it appears (on a terminal or
// a pipe that is not the journal, the line begins with its time).
TEST(ServeAtBoot, StartsWithItsPortMissingAndConnectsWhenTheSensorAppears) {
  TempDir dir;
  const auto port = (dir.path / "later").string();
  const auto site = (dir.path / "site.toml").string();
  std::ofstream(site) << "[service]\nlisten = \"127.0.0.1:0\"\n[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\n"
                         "port = \""
                      << port << "\"\n";
  Service service({rangekit::test::cli_path(), "serve", "--config", site}, {}, false);
  const auto missing =
      service.line_with("belt: disconnected: cannot open serial port " + port, std::chrono::seconds(20));
  ASSERT_TRUE(missing.has_value()) << service.output();
  EXPECT_EQ(missing->rfind("2", 0), 0U) << "not the journal: the line begins with its time: " << *missing;
  ASSERT_TRUE(service.running()) << service.output();

  Child sim({"sim", "ls5", "--port", port});
  ASSERT_TRUE(cli_test::contains(sim.read_line(), "ready")) << "the emulator did not start";
  EXPECT_TRUE(service.line_with("belt: streaming", std::chrono::seconds(30)).has_value()) << service.output();
  EXPECT_EQ(service.terminate(), 130) << service.output();
}

}  // namespace
