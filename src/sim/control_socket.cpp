#include "rangekit/sim/control_socket.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "rangekit/core/fd_transport.hpp"
#include "rangekit/core/text.hpp"

namespace rangekit {
namespace {

constexpr std::size_t max_line = std::size_t{64} * 1024;

Result<sockaddr_un> unix_address(const std::string& path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.size() >= sizeof(address.sun_path)) {
    return make_error(Errc::overlong, "control socket path is longer than " +
                                          std::to_string(sizeof(address.sun_path) - 1) + " characters: " + path);
  }
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  return address;
}

bool write_line(int fd, const std::string& line) {
  std::size_t done = 0;
  while (done < line.size()) {
    const ssize_t n = ::send(fd, line.data() + done, line.size() - done, MSG_NOSIGNAL);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      pollfd waiter{fd, POLLOUT, 0};
      if (::poll(&waiter, 1, 1000) <= 0) return false;
      continue;
    }
    return false;
  }
  return true;
}

}  // namespace

Result<std::unique_ptr<ControlSocket>> ControlSocket::listen(const std::string& path) {
  auto address = unix_address(path);
  if (!address) return address.error();
  struct stat existing {};
  if (::lstat(path.c_str(), &existing) == 0) {
    return make_error(Errc::io, path + " already exists; remove it or choose another control path");
  }
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) return make_error(Errc::io, errno_text("socket", errno));
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&address.value()), sizeof(sockaddr_un)) != 0) {
    const int error_number = errno;
    ::close(fd);
    return make_error(Errc::io, errno_text("cannot listen on " + path, error_number));
  }
  // Owner only whatever the umask: no peer can connect before listen(), and umask() would be
  // process-wide, racing with other threads that create files.
  if (::chmod(path.c_str(), 0600) != 0 || ::listen(fd, 8) != 0) {
    const int error_number = errno;
    ::close(fd);
    ::unlink(path.c_str());
    return make_error(Errc::io, errno_text("cannot listen on " + path, error_number));
  }
  return std::unique_ptr<ControlSocket>(new ControlSocket(fd, path));
}

ControlSocket::~ControlSocket() {
  for (const auto& client : clients_) ::close(client.fd);
  ::close(listener_);
  ::unlink(path_.c_str());
}

void ControlSocket::add_poll_fds(std::vector<pollfd>& fds) const {
  fds.push_back(pollfd{listener_, POLLIN, 0});
  for (const auto& client : clients_) fds.push_back(pollfd{client.fd, POLLIN, 0});
}

void ControlSocket::service(const Handler& handler) {
  while (true) {
    const int fd = ::accept4(listener_, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
    if (fd < 0) break;
    clients_.push_back(Client{fd, {}});
  }
  for (auto& client : clients_) {
    // Reads stop one byte past the limit, where the connection ends, so no more than that is
    // ever held for a peer; the budget keeps one busy peer from holding up the loop (poll
    // reports the rest again).
    std::array<char, 4096> buffer{};
    std::size_t budget = max_line;
    while (client.fd >= 0 && budget > 0 && client.pending.size() <= max_line) {
      const std::size_t room = max_line + 1 - client.pending.size();
      const ssize_t n = ::recv(client.fd, buffer.data(), std::min({buffer.size(), budget, room}), 0);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) close_client(client);
        break;
      }
      budget -= static_cast<std::size_t>(n);
      client.pending.append(buffer.data(), static_cast<std::size_t>(n));
      peak_pending_ = std::max(peak_pending_, client.pending.size());
    }
    // Answered after reading, not between reads: a request that comes in after an answer waits
    // for the next turn of the loop, which polls the serial lines first (the tests' "status"
    // request relies on that order).
    answer_lines(handler, client);
    if (client.fd >= 0 && client.pending.size() > max_line) {
      (void)write_line(client.fd, nlohmann::json{{"error", "request line longer than 64 KiB"}}.dump() + "\n");
      close_client(client);
    }
  }
  std::erase_if(clients_, [](const Client& client) { return client.fd < 0; });
}

void ControlSocket::close_client(Client& client) {
  ::close(client.fd);
  client.fd = -1;
  client.pending.clear();
  client.pending.shrink_to_fit();
}

void ControlSocket::answer_lines(const Handler& handler, Client& client) {
  std::size_t newline = 0;
  while (client.fd >= 0 && (newline = client.pending.find('\n')) != std::string::npos) {
    const std::string line = client.pending.substr(0, newline);
    client.pending.erase(0, newline + 1);
    if (line.empty()) continue;
    if (!write_line(client.fd, answer_control_line(handler, line) + "\n")) close_client(client);
  }
}

Result<ControlClient> ControlClient::connect(const std::string& path) {
  auto address = unix_address(path);
  if (!address) return address.error();
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return make_error(Errc::io, errno_text("socket", errno));
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address.value()), sizeof(sockaddr_un)) != 0) {
    const int error_number = errno;
    ::close(fd);
    return make_error(Errc::io, errno_text("cannot connect to control socket " + path, error_number));
  }
  return ControlClient(fd);
}

ControlClient::ControlClient(ControlClient&& other) noexcept : fd_(other.fd_), pending_(std::move(other.pending_)) {
  other.fd_ = -1;
}

ControlClient& ControlClient::operator=(ControlClient&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_;
    pending_ = std::move(other.pending_);
    other.fd_ = -1;
  }
  return *this;
}

ControlClient::~ControlClient() {
  if (fd_ >= 0) ::close(fd_);
}

Result<nlohmann::json> ControlClient::request(const nlohmann::json& request, int timeout_ms) {
  return request_line(safe_dump(request), timeout_ms);
}

Result<nlohmann::json> ControlClient::request_line(const std::string& text, int timeout_ms) {
  if (fd_ < 0) return make_error(Errc::closed, "control connection is closed");
  if (!write_line(fd_, text + "\n")) return make_error(Errc::closed, "control socket: cannot send");
  while (true) {
    const auto newline = pending_.find('\n');
    if (newline != std::string::npos) {
      const std::string line = pending_.substr(0, newline);
      pending_.erase(0, newline + 1);
      auto reply = nlohmann::json::parse(line, nullptr, false);
      if (reply.is_discarded()) return make_error(Errc::invalid_frame, "control reply is not JSON: " + line);
      return reply;
    }
    pollfd waiter{fd_, POLLIN, 0};
    const int ready = ::poll(&waiter, 1, timeout_ms);
    if (ready == 0) return make_error(Errc::timeout, "no control reply within " + std::to_string(timeout_ms) + " ms");
    if (ready < 0 && errno == EINTR) continue;
    char buffer[4096];
    const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
    if (n <= 0) return make_error(Errc::closed, "control socket closed by the emulator");
    pending_.append(buffer, static_cast<std::size_t>(n));
  }
}

std::string answer_control_line(const ControlSocket::Handler& handler, const std::string& line) {
  nlohmann::json request = nlohmann::json::parse(line, nullptr, false);
  if (request.is_discarded() || !request.is_object()) {
    return safe_dump({{"error", "not a JSON object (or not valid UTF-8): " + text::printable(line, true)}});
  }
  try {
    return safe_dump(handler(request));
  } catch (const std::exception& error) {
    // A request with fields of the wrong type (nlohmann throws type_error).
    return safe_dump({{"error", std::string("bad request: ") + error.what()}});
  }
}

Result<double> control_number(const nlohmann::json& request, std::string_view key, double min, double max,
                              std::optional<double> fallback) {
  const std::string command = request.contains("cmd") && request.at("cmd").is_string()
                                  ? request.at("cmd").get<std::string>()
                                  : std::string("request");
  const auto shortest = [](double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return std::string(text);
  };
  const std::string range = "within " + shortest(min) + " .. " + shortest(max);
  const std::string name(key);
  const auto found = request.find(std::string(key));
  if (found == request.end()) {
    if (fallback) return *fallback;
    return make_error(Errc::out_of_range, command + ": needs '" + name + "' (a number " + range + ")");
  }
  const double value = found->is_number() ? found->get<double>() : std::nan("");
  // NaN fails both comparisons; JSON has no infinity, but a double can overflow to it (1e999).
  if (!(value >= min && value <= max)) {
    return make_error(Errc::out_of_range,
                      command + ": '" + name + "' must be a number " + range + ", not " + safe_dump(*found));
  }
  return value;
}

std::string safe_dump(const nlohmann::json& value) {
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace rangekit
