#include "rangekit/mqtt/local_broker.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

namespace rangekit::mqtt {
namespace {

sockaddr_in loopback(std::uint16_t port) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return address;
}

// A port the kernel hands out now; the broker binds it a moment later (retried on a clash).
std::uint16_t free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return 0;
  sockaddr_in address = loopback(0);
  socklen_t length = sizeof address;
  std::uint16_t port = 0;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0) {
    port = ntohs(address.sin_port);
  }
  ::close(fd);
  return port;
}

bool accepts(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  sockaddr_in address = loopback(port);
  const bool connected = ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
  ::close(fd);
  return connected;
}

// Whether process `pid` itself listens on 127.0.0.1:port. A connect() alone would also be
// answered by another broker that took the port first (tests start many at once), while
// ours exits with "address in use"; the socket's inode in /proc tells whose it is.
// Until the child has become `executable` (a canonical path), it holds copies of the forking process's
// descriptors (a listener of the caller's among them), so it does not count as listening.
// nullopt: /proc cannot say (then a connect() is all there is).
std::optional<bool> listens(pid_t pid, std::uint16_t port, const std::filesystem::path& executable) {
  const std::filesystem::path process = "/proc/" + std::to_string(pid);
  std::error_code error;
  const auto running = std::filesystem::read_symlink(process / "exe", error);
  // An exited child (a zombie) has no executable to read: not listening, if /proc works at all.
  if (error) return std::filesystem::exists("/proc/self/exe", error) ? std::optional<bool>(false) : std::nullopt;
  if (running != executable) return false;
  std::ifstream table("/proc/net/tcp");
  std::filesystem::directory_iterator entries(process / "fd", error);
  if (!table || error) return std::nullopt;
  char wanted[16];
  std::snprintf(wanted, sizeof wanted, "0100007F:%04X", port);
  std::set<std::string> sockets;
  std::string line;
  std::getline(table, line);  // the heading
  while (std::getline(table, line)) {
    std::istringstream fields(line);
    std::string slot, local, remote, state, queues, timer, retransmits, uid, timeout, inode;
    fields >> slot >> local >> remote >> state >> queues >> timer >> retransmits >> uid >> timeout >> inode;
    if (local == wanted && state == "0A") sockets.insert("socket:[" + inode + "]");
  }
  if (sockets.empty()) return false;
  for (const auto& entry : entries) {
    const auto target = std::filesystem::read_symlink(entry.path(), error);
    if (!error && sockets.contains(target.string())) return true;
  }
  return false;
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

}  // namespace

std::string LocalBroker::find_executable() {
  std::vector<std::string> places;
  if (const char* path = std::getenv("PATH")) {  // NOLINT(concurrency-mt-unsafe): read once, nothing sets it
    std::stringstream folders(path);
    for (std::string folder; std::getline(folders, folder, ':');) places.push_back(folder + "/mosquitto");
  }
  places.emplace_back("/usr/sbin/mosquitto");
  places.emplace_back("/usr/local/sbin/mosquitto");
  for (const std::string& place : places) {
    if (::access(place.c_str(), X_OK) == 0) return place;
  }
  return {};
}

Result<std::unique_ptr<LocalBroker>> LocalBroker::start(LocalBrokerOptions options) {
  if (options.executable.empty()) options.executable = find_executable();
  if (options.executable.empty()) {
    return make_error(Errc::unsupported, "no mosquitto installed (Debian: apt-get install mosquitto)");
  }
  const bool pick = options.port == 0;
  std::unique_ptr<LocalBroker> broker(new LocalBroker(std::move(options)));
  Status started = ok_status();
  for (int attempt = 0; attempt < 5; ++attempt) {
    if (pick) broker->options_.port = free_port();
    started = broker->launch();
    if (started || !pick) break;
  }
  if (!started) return std::move(started).error();
  return broker;
}

Status LocalBroker::launch() {
  const auto config_path = options_.dir / "mosquitto.conf";
  {
    std::ofstream config(config_path);
    config << "# written by rangekit for a loopback broker of its own\n"
           << "listener " << options_.port << " 127.0.0.1\n"
           << "user root\n"  // started as root it would switch to 'mosquitto', who cannot read this folder
           << "persistence false\n"
           << "set_tcp_nodelay true\n"  // deliveries leave at once, not after a delayed ACK
           << "log_dest stderr\n";
    if (options_.password_file.empty()) {
      config << "allow_anonymous true\n";
    } else {
      config << "allow_anonymous false\npassword_file " << options_.password_file << "\n";
    }
    if (options_.max_packet_size > 0) config << "max_packet_size " << options_.max_packet_size << "\n";
    config << options_.extra_config;
    if (!config.flush()) return make_error(Errc::io, "cannot write " + config_path.string());
  }
  // Made before fork: the child of a threaded process may call async-signal-safe functions only.
  const std::string log = log_path();
  const std::string config = config_path.string();
  const char* const executable = options_.executable.c_str();
  // Once, not at each poll: what /proc/PID/exe reads once the child runs mosquitto.
  std::error_code unresolved;
  const std::filesystem::path running_executable = std::filesystem::weakly_canonical(executable, unresolved);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) return make_error(Errc::io, "cannot start mosquitto: fork failed");
  if (pid == 0) {
    // Its own process group: a Ctrl-C in the terminal reaches the service, which stops the broker last.
    ::setpgid(0, 0);
    // A service that dies without stopping it (kill -9, a crash) takes the broker along; the
    // signal comes when the forking thread ends, hence start() and restart() on a lasting thread.
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) ::_exit(127);  // the service died before the prctl: no signal would come
    sigset_t none;  // a mask inherited from the forking thread would hold the death signal back
    ::sigemptyset(&none);
    ::pthread_sigmask(SIG_SETMASK, &none, nullptr);
    const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
    const int null = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
    ::dup2(null, STDIN_FILENO);
    ::dup2(out, STDOUT_FILENO);
    ::dup2(out, STDERR_FILENO);
    // None of the service's descriptors (its listening sockets among them) stay open in the broker.
    ::close_range(3, ~0U, 0);
    ::execl(executable, executable, "-c", config.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  pid_ = pid;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    const std::optional<bool> ours = listens(pid_, options_.port, running_executable);
    if (ours ? *ours : accepts(options_.port)) return ok_status();
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return make_error(Errc::io,
                        "mosquitto on port " + std::to_string(options_.port) + " exited at start: " + read_text(log));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));  // polls a port that is not open yet
  }
  stop();
  return make_error(Errc::timeout, "mosquitto did not listen on 127.0.0.1:" + std::to_string(options_.port));
}

void LocalBroker::kill_hard() {
  if (pid_ <= 0) return;
  ::kill(pid_, SIGKILL);
  ::waitpid(pid_, nullptr, 0);
  pid_ = -1;
}

Status LocalBroker::restart() {
  stop();
  return launch();
}

void LocalBroker::stop() {
  if (pid_ <= 0) return;
  ::kill(pid_, SIGTERM);
  ::waitpid(pid_, nullptr, 0);
  pid_ = -1;
}

LocalBroker::~LocalBroker() { stop(); }

}  // namespace rangekit::mqtt
