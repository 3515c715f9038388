// The live status line (docs/cli.md "Terminal and pipe"): drawn when standard
// output is a terminal, absent when stdout is a pipe (a program reads it) and
// with --quiet. The terminal here is a pty; the stream comes from the LS5 emulator.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "cli/cli_run.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/sim/pty.hpp"

namespace {

using ls5_driver_test::Child;

using cli_test::contains;

struct Captured {
  int exit_code = -1;
  std::string terminal;  // what reached the pty (stderr, and stdout when it is the pty)
  std::string piped;     // stdout when it is a pipe
};

std::string read_all(int fd) {
  std::string text;
  char buffer[4096];
  for (;;) {
    const ssize_t got = ::read(fd, buffer, sizeof buffer);
    if (got <= 0) return text;
    text.append(buffer, static_cast<std::size_t>(got));
  }
}

// Runs the CLI with stderr on a pty and stdout on the same pty or on a pipe.
Captured run_on_terminal(const std::vector<std::string>& arguments, bool stdout_is_terminal) {
  Captured result;
  auto terminal = rangekit::PseudoTerminal::open();
  if (!terminal) return result;
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) return result;
  const pid_t pid = rangekit::test::fork_child();
  if (pid == 0) {
    ::setsid();
    const int slave = ::open((*terminal)->slave_path().c_str(), O_RDWR);
    ::dup2(slave, STDERR_FILENO);
    ::dup2(stdout_is_terminal ? slave : pipe_fds[1], STDOUT_FILENO);
    Child::exec(arguments);
  }
  ::close(pipe_fds[1]);
  // The pty reads EIO once the child, its only slave holder, has exited.
  const int master = (*terminal)->native_handle();
  for (;;) {
    pollfd descriptor{master, POLLIN, 0};
    if (::poll(&descriptor, 1, 30000) <= 0) break;
    char buffer[4096];
    const ssize_t got = ::read(master, buffer, sizeof buffer);
    if (got <= 0) break;
    result.terminal.append(buffer, static_cast<std::size_t>(got));
  }
  result.piped = read_all(pipe_fds[0]);
  ::close(pipe_fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

class StatusLine : public ::testing::Test {
 protected:
  void SetUp() override {
    port_ = (dir_ / "ls5").string();
    sim_ = std::make_unique<Child>(std::vector<std::string>{"sim", "ls5", "--port", port_});
    ASSERT_TRUE(contains(sim_->read_line(), "ready:"));
  }
  std::vector<std::string> stream(const std::vector<std::string>& extra = {}) const {
    std::vector<std::string> arguments{"ls5", "stream", "--port", port_, "--count", "20", "--format", "jsonl"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return arguments;
  }
  ls5_driver_test::TempDir temp_;  // declared first: removed after the emulator stops
  const std::filesystem::path& dir_ = temp_.path;
  std::string port_;
  std::unique_ptr<Child> sim_;
};

TEST_F(StatusLine, DrawnWhenStdoutIsATerminal) {
  const Captured run = run_on_terminal(stream(), true);
  ASSERT_EQ(run.exit_code, 0) << run.terminal;
  EXPECT_TRUE(contains(run.terminal, "\"device\":\"ls5\"")) << run.terminal;
  // The closing status line: count, rate, errors, lost, disconnects.
  EXPECT_TRUE(contains(run.terminal, "20 samples")) << run.terminal;
  EXPECT_TRUE(contains(run.terminal, "errors 0  lost 0  disconnects 0")) << run.terminal;
}

TEST_F(StatusLine, AbsentWhenStdoutIsAPipe) {
  const Captured run = run_on_terminal(stream(), false);
  ASSERT_EQ(run.exit_code, 0) << run.terminal;
  std::size_t lines = 0;
  for (const char c : run.piped) lines += c == '\n' ? 1 : 0;
  EXPECT_EQ(lines, 21U) << run.piped;  // the `connected` event (L69), then the 20 samples
  EXPECT_FALSE(contains(run.piped, "samples")) << run.piped;
  EXPECT_FALSE(contains(run.terminal, "samples")) << run.terminal;
  EXPECT_FALSE(contains(run.terminal, "\r\x1b[K")) << run.terminal;
}

TEST_F(StatusLine, QuietTurnsItOffOnATerminal) {
  const Captured run = run_on_terminal(stream({"--quiet"}), true);
  ASSERT_EQ(run.exit_code, 0) << run.terminal;
  EXPECT_TRUE(contains(run.terminal, "\"device\":\"ls5\"")) << run.terminal;
  EXPECT_FALSE(contains(run.terminal, "samples")) << run.terminal;
}

// No silent waits (docs/cli.md): `detect` shows progress on a terminal. A pty
// where nothing answers stands for a port without a sensor.
TEST(DetectProgress, ShownOnATerminalAndNotInAPipe) {
  auto silent = rangekit::PseudoTerminal::open();
  ASSERT_TRUE(silent);
  const std::vector<std::string> detect{"detect",        "--port", (*silent)->slave_path(), "--baud", "9600",
                                        "--byte-format", "8N1",    "--timeout-ms",          "20"};
  const Captured shown = run_on_terminal(detect, true);
  EXPECT_EQ(shown.exit_code, 5) << shown.terminal;  // docs/cli.md: 5 when nothing answered
  EXPECT_TRUE(contains(shown.terminal, "rangekit detect: trying " + (*silent)->slave_path() + " at 9600 8N1"))
      << shown.terminal;
  const Captured piped = run_on_terminal(detect, false);
  EXPECT_EQ(piped.exit_code, 5) << piped.terminal;
  EXPECT_FALSE(contains(piped.terminal, "trying")) << piped.terminal;
}

}  // namespace
