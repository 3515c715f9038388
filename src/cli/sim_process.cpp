#include "cli/sim_process.hpp"
#include "rangekit/core/fd_transport.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <utility>

namespace rangekit::cli {
namespace {

// Waits for the child to exit for up to `limit`; true when it has.
bool reap_within(pid_t pid, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (true) {
    int status = 0;
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid || (done < 0 && errno == ECHILD)) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    // waitpid has no timeout; poll on nothing for a short while between checks.
    ::poll(nullptr, 0, 10);
  }
}

}  // namespace

Result<SimProcess> SimProcess::start(const std::vector<std::string>& arguments, const std::string& log_path,
                                     std::chrono::milliseconds timeout, const std::string& executable) {
  std::array<int, 2> ready_pipe{};
  if (::pipe2(ready_pipe.data(), O_CLOEXEC) != 0) return make_error(Errc::io, errno_text("pipe", errno));
  const int log_fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (log_fd < 0) {
    ::close(ready_pipe[0]);
    ::close(ready_pipe[1]);
    return make_error(Errc::io, errno_text("cannot create " + log_path, errno));
  }
  std::vector<std::string> argv_strings{"rangekit", "sim"};
  argv_strings.insert(argv_strings.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  argv.reserve(argv_strings.size() + 1);
  for (auto& argument : argv_strings) argv.push_back(argument.data());
  argv.push_back(nullptr);

  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int error_number = errno;
    ::close(ready_pipe[0]);
    ::close(ready_pipe[1]);
    ::close(log_fd);
    return make_error(Errc::io, errno_text("fork", error_number));
  }
  if (pid == 0) {
    // Its own process group, so that Ctrl-C on the terminal reaches the parent only and
    // the parent stops it after ending its streams; SIGTERM when the parent dies anyway.
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) ::_exit(127);
    sigset_t none;  // a mask inherited from the forking thread would hold the death signal back
    ::sigemptyset(&none);
    ::pthread_sigmask(SIG_SETMASK, &none, nullptr);
    ::dup2(ready_pipe[1], STDOUT_FILENO);
    ::dup2(log_fd, STDERR_FILENO);
    // None of the parent's descriptors (a service's listening sockets among them) stay open in it.
    ::close_range(3, ~0U, 0);
    ::execv(executable.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(ready_pipe[1]);
  ::close(log_fd);

  std::string output;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (output.find('\n') == std::string::npos) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    pollfd descriptor{ready_pipe[0], POLLIN, 0};
    if (left.count() <= 0 || ::poll(&descriptor, 1, static_cast<int>(left.count())) <= 0) break;
    std::array<char, 512> buffer{};
    const ssize_t got = ::read(ready_pipe[0], buffer.data(), buffer.size());
    if (got <= 0) break;
    output.append(buffer.data(), static_cast<std::size_t>(got));
  }
  ::close(ready_pipe[0]);
  SimProcess process(pid, output.substr(0, output.find('\n')));
  if (process.ready_line_.find("ready:") == std::string::npos) {
    process.stop();
    return make_error(Errc::io, "emulator `rangekit sim " + (arguments.empty() ? std::string() : arguments[0]) +
                                    "` did not start; see " + log_path);
  }
  return process;
}

SimProcess::SimProcess(SimProcess&& other) noexcept
    : pid_(std::exchange(other.pid_, -1)), ready_line_(std::move(other.ready_line_)) {}

SimProcess& SimProcess::operator=(SimProcess&& other) noexcept {
  if (this != &other) {
    stop();
    pid_ = std::exchange(other.pid_, -1);
    ready_line_ = std::move(other.ready_line_);
  }
  return *this;
}

SimProcess::~SimProcess() { stop(); }

void SimProcess::stop() noexcept {
  if (pid_ <= 0) return;
  ::kill(pid_, SIGTERM);
  if (!reap_within(pid_, std::chrono::seconds(2))) {
    ::kill(pid_, SIGKILL);
    reap_within(pid_, std::chrono::seconds(2));
  }
  pid_ = -1;
}

}  // namespace rangekit::cli
