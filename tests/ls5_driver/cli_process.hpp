// Child processes of the built `rangekit` binary for the end-to-end tests: an
// emulator or a long-running stream read line by line from a pipe (blocking
// reads, never sleeps), and one-shot subcommands with their output and exit code.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include "build_paths.hpp"
#include "child_process.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace ls5_driver_test {

class Child {
 public:
  explicit Child(const std::vector<std::string>& arguments) {
    int out[2];
    if (::pipe2(out, O_CLOEXEC) != 0) return;
    pid_ = rangekit::test::fork_child();
    if (pid_ == 0) {
      ::dup2(out[1], STDOUT_FILENO);
      exec(arguments);
    }
    ::close(out[1]);
    stdout_ = ::fdopen(out[0], "r");
  }
  ~Child() {
    if (pid_ > 0 && !exited_) rangekit::test::end_child(pid_);
    if (stdout_ != nullptr) std::fclose(stdout_);
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  // The next line of its stdout; empty at end of file.
  std::string read_line() {
    char buffer[4096];
    if (stdout_ == nullptr || std::fgets(buffer, sizeof buffer, stdout_) == nullptr) return {};
    return buffer;
  }
  void terminate() const { ::kill(pid_, SIGTERM); }
  [[nodiscard]] pid_t pid() const { return pid_; }
  // kill -9: the child cleans nothing up (its symlink and control socket stay).
  void kill_hard() {
    ::kill(pid_, SIGKILL);
    (void)wait();
  }
  int wait() {
    int status = 0;
    ::waitpid(pid_, &status, 0);
    exited_ = true;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  [[noreturn]] static void exec(const std::vector<std::string>& arguments) {
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(rangekit::test::cli_path()));
    for (const auto& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(rangekit::test::cli_path(), argv.data());
    ::_exit(127);
  }

 private:
  pid_t pid_ = -1;
  FILE* stdout_ = nullptr;
  bool exited_ = false;
};

// A fresh directory for one test's ports, logs and output files, removed afterwards
// (also when an assertion ends the test early).
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "rangekit-test-XXXXXX").string();
    if (::mkdtemp(pattern.data()) != nullptr) path = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    if (!path.empty()) std::filesystem::remove_all(path, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

struct CliRun {
  int exit_code = -1;
  std::string out;
  std::string err;
};

inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

// Runs `rangekit ARGS...` to the end; stdout and stderr through files in `dir`.
inline CliRun run_cli(const std::filesystem::path& dir, const std::vector<std::string>& arguments) {
  const auto out_path = dir / "cli.out";
  const auto err_path = dir / "cli.err";
  const pid_t pid = rangekit::test::fork_child();
  if (pid == 0) {
    const int out = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    ::dup2(out, STDOUT_FILENO);
    ::dup2(err, STDERR_FILENO);
    Child::exec(arguments);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  CliRun run;
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.out = read_file(out_path);
  run.err = read_file(err_path);
  return run;
}

}  // namespace ls5_driver_test
