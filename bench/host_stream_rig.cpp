#include "host_stream_rig.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <utility>

#ifndef RANGEKIT_CLI_PATH
#error "RANGEKIT_CLI_PATH (the rangekit CLI binary) is set by CMakeLists.txt for rangekit_bench"
#endif

namespace rangekit::bench {
namespace {

std::string errno_text() { return std::strerror(errno); }

// Waits for the child to exit for up to `limit` (waitpid has no timeout: a
// short poll on nothing between checks); true when it has.
bool reap_within(pid_t pid, std::chrono::milliseconds limit, rusage* usage = nullptr) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (true) {
    int status = 0;
    const pid_t done = ::wait4(pid, &status, WNOHANG, usage);
    if (done == pid || (done < 0 && errno == ECHILD)) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    ::poll(nullptr, 0, 10);
  }
}

void stop_child(pid_t pid, rusage* usage = nullptr) {
  if (pid <= 0) return;
  ::kill(pid, SIGTERM);
  if (!reap_within(pid, std::chrono::seconds(2), usage)) {
    ::kill(pid, SIGKILL);
    reap_within(pid, std::chrono::seconds(2), usage);
  }
}

double seconds(const timeval& t) { return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) / 1e6; }

}  // namespace

ScratchDir::ScratchDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "rangekit-host-stream-XXXXXX").string();
  if (::mkdtemp(pattern.data()) != nullptr) path_ = pattern;
}

ScratchDir::~ScratchDir() {
  std::error_code ignored;
  if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
}

Result<std::unique_ptr<EmulatorProcess>> EmulatorProcess::start(const std::vector<std::string>& arguments,
                                                                const std::string& log_path,
                                                                std::chrono::milliseconds timeout) {
  std::array<int, 2> ready_pipe{};
  if (::pipe2(ready_pipe.data(), O_CLOEXEC) != 0) return make_error(Errc::io, "pipe: " + errno_text());
  const int log_fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (log_fd < 0) {
    ::close(ready_pipe[0]);
    ::close(ready_pipe[1]);
    return make_error(Errc::io, "cannot create " + log_path + ": " + errno_text());
  }
  std::vector<std::string> argv_strings{"rangekit", "sim"};
  argv_strings.insert(argv_strings.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (auto& argument : argv_strings) argv.push_back(argument.data());
  argv.push_back(nullptr);

  const pid_t pid = ::fork();
  if (pid < 0) return make_error(Errc::io, "fork: " + errno_text());
  if (pid == 0) {
    ::dup2(ready_pipe[1], STDOUT_FILENO);
    ::dup2(log_fd, STDERR_FILENO);
    ::execv(RANGEKIT_CLI_PATH, argv.data());
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
  std::unique_ptr<EmulatorProcess> process(new EmulatorProcess(pid, output.substr(0, output.find('\n'))));
  if (process->ready_line_.find("ready:") == std::string::npos) {
    return make_error(Errc::io, "`rangekit sim " + (arguments.empty() ? std::string() : arguments[0]) +
                                    "` did not start; see " + log_path);
  }
  return process;
}

EmulatorProcess::~EmulatorProcess() { stop_child(pid_); }

Result<nlohmann::json> control(const std::string& socket_path, const nlohmann::json& request) {
  auto client = ControlClient::connect(socket_path);
  if (!client) return std::move(client).error();
  auto reply = client->request(request, 2000);
  if (!reply) return std::move(reply).error();
  if (reply->contains("error")) return make_error(Errc::io, "control: " + reply->at("error").dump());
  return reply;
}

Result<std::size_t> CountingTransport::read_some(std::span<std::uint8_t> out, std::chrono::milliseconds timeout) {
  auto got = inner_->read_some(out, timeout);
  if (got) bytes_->fetch_add(*got, std::memory_order_relaxed);
  return got;
}

double process_cpu_s() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

CatCopy::CatCopy(pid_t pid, int fd, std::filesystem::path out) : pid_(pid), fd_(fd), out_(std::move(out)) {}

Result<std::unique_ptr<CatCopy>> CatCopy::start(const std::string& tty_path, const std::filesystem::path& out) {
  const int fd = ::open(tty_path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return make_error(Errc::io, "open " + tty_path + ": " + errno_text());
  termios settings{};
  if (::tcgetattr(fd, &settings) != 0) {
    ::close(fd);
    return make_error(Errc::io, "tcgetattr " + tty_path + ": " + errno_text());
  }
  settings.c_cc[VMIN] = 1;  // speed and raw mode stay as the host set them
  settings.c_cc[VTIME] = 0;
  ::tcsetattr(fd, TCSANOW, &settings);
  const int file = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (file < 0) {
    ::close(fd);
    return make_error(Errc::io, "cannot create " + out.string() + ": " + errno_text());
  }
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fd);
    ::close(file);
    return make_error(Errc::io, "fork: " + errno_text());
  }
  if (pid == 0) {
    ::dup2(fd, STDIN_FILENO);
    ::dup2(file, STDOUT_FILENO);
    ::execlp("cat", "cat", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(file);
  return std::unique_ptr<CatCopy>(new CatCopy(pid, fd, out));
}

CatCopy::~CatCopy() {
  stop_child(pid_);
  if (fd_ >= 0) ::close(fd_);
}

Status CatCopy::send(std::string_view text) {
  if (::write(fd_, text.data(), text.size()) != static_cast<ssize_t>(text.size())) {
    return make_error(Errc::io, "write to the pty: " + errno_text());
  }
  return ok_status();
}

std::uintmax_t CatCopy::file_bytes() const {
  std::error_code error;
  const auto size = std::filesystem::file_size(out_, error);
  return error ? 0 : size;
}

double CatCopy::finish(std::string_view ending, std::chrono::milliseconds limit) {
  // The stream was stopped and the device answered the stop request: cat has
  // copied everything once the file ends with that answer (checked every 10 ms
  // against a deadline).
  const auto deadline = std::chrono::steady_clock::now() + limit;
  auto copied = [&] {
    const auto size = file_bytes();
    if (size < ending.size()) return false;
    std::ifstream in(out_, std::ios::binary);
    in.seekg(static_cast<std::streamoff>(size - ending.size()));
    std::string tail(ending.size(), '\0');
    in.read(tail.data(), static_cast<std::streamsize>(tail.size()));
    return tail == ending;
  };
  while (!copied() && std::chrono::steady_clock::now() < deadline) ::poll(nullptr, 0, 10);
  rusage usage{};
  stop_child(pid_, &usage);
  pid_ = -1;
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace rangekit::bench
