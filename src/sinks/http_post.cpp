// POSIX sockets and poll(): each wait is bounded by what is left of the deadline, so a
// historian that stops answering holds the sink at most `timeout`.
#include "sinks/http_post.hpp"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <optional>
#include <system_error>

namespace rangekit::sinks {
namespace {

using Clock = std::chrono::steady_clock;

class Socket {
 public:
  explicit Socket(int fd) : fd_(fd) {}
  ~Socket() {
    if (fd_ >= 0) ::close(fd_);
  }
  Socket(const Socket&) = delete;
  Socket& operator=(const Socket&) = delete;
  [[nodiscard]] int fd() const noexcept { return fd_; }

 private:
  int fd_;
};

// Waits for `events` on the socket until the deadline; false on timeout.
bool wait_for(int fd, short events, Clock::time_point deadline) {
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return false;
    pollfd poll_fd{fd, events, 0};
    const int ready = ::poll(&poll_fd, 1, static_cast<int>(left));
    if (ready > 0) return true;
    if (ready < 0 && errno != EINTR) return false;
  }
}

Result<int> connect_to(const hub::HttpUrl& url, Clock::time_point deadline) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  const std::string port = std::to_string(url.port);
  if (const int failed = ::getaddrinfo(url.host.c_str(), port.c_str(), &hints, &found); failed != 0) {
    return make_error(Errc::io, url.host + ": " + ::gai_strerror(failed));
  }
  std::string why = "no address";
  for (const addrinfo* at = found; at != nullptr; at = at->ai_next) {
    const int fd = ::socket(at->ai_family, at->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, at->ai_protocol);
    if (fd < 0) continue;
    if (::connect(fd, at->ai_addr, at->ai_addrlen) == 0 || (errno == EINPROGRESS && wait_for(fd, POLLOUT, deadline))) {
      int error = 0;
      socklen_t size = sizeof error;
      ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &size);
      if (error == 0) {
        ::freeaddrinfo(found);
        return fd;
      }
      why = std::system_category().message(error);
    } else {
      why = errno == EINPROGRESS ? "connect timed out" : std::system_category().message(errno);
    }
    ::close(fd);
  }
  ::freeaddrinfo(found);
  return make_error(Errc::io, "connect " + url.host + ":" + port + ": " + why);
}

Status send_all(int fd, std::string_view bytes, Clock::time_point deadline) {
  while (!bytes.empty()) {
    const ssize_t sent = ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (sent > 0) {
      bytes.remove_prefix(static_cast<std::size_t>(sent));
    } else if (sent < 0 && (errno == EAGAIN || errno == EINTR)) {
      if (!wait_for(fd, POLLOUT, deadline)) return make_error(Errc::timeout, "send timed out");
    } else {
      return make_error(Errc::io, std::string("send: ") + std::system_category().message(errno));
    }
  }
  return ok_status();
}

// The Content-Length header's value, or none.
std::optional<std::size_t> content_length(std::string_view head) {
  std::string lower(head);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const auto at = lower.find("\r\ncontent-length:");
  if (at == std::string::npos) return std::nullopt;
  std::size_t from = at + 17;
  while (from < lower.size() && lower[from] == ' ') ++from;
  std::size_t value = 0;
  const auto [end, error] = std::from_chars(lower.data() + from, lower.data() + lower.size(), value);
  if (error != std::errc{}) return std::nullopt;
  return value;
}

}  // namespace

Result<HttpAnswer> http_post(const hub::HttpUrl& url, std::string_view content_type, std::string_view body,
                             std::chrono::milliseconds timeout, std::size_t max_answer) {
  const auto deadline = Clock::now() + timeout;
  auto fd = connect_to(url, deadline);
  if (!fd) return std::move(fd).error();
  const Socket socket(*fd);
  std::string request = "POST " + url.path + " HTTP/1.1\r\nHost: " + url.host + ":" + std::to_string(url.port) +
                        "\r\nContent-Type: " + std::string(content_type) +
                        "\r\nContent-Length: " + std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n";
  if (auto sent = send_all(socket.fd(), request, deadline); !sent) return std::move(sent).error();
  if (auto sent = send_all(socket.fd(), body, deadline); !sent) return std::move(sent).error();
  std::string answer;
  std::array<char, 65536> buffer{};
  for (;;) {
    if (answer_complete(answer, max_answer)) break;
    const ssize_t got = ::recv(socket.fd(), buffer.data(), buffer.size(), 0);
    if (got > 0) {
      answer.append(buffer.data(), static_cast<std::size_t>(got));
    } else if (got == 0) {
      break;  // Connection: close: the answer ends with the connection
    } else if (errno == EAGAIN || errno == EINTR) {
      if (!wait_for(socket.fd(), POLLIN, deadline)) return make_error(Errc::timeout, "no answer in time");
    } else {
      return make_error(Errc::io, std::string("recv: ") + std::system_category().message(errno));
    }
  }
  return parse_http_answer(answer);
}

bool answer_complete(std::string_view answer, std::size_t max_answer) {
  if (answer.size() >= max_answer) return true;
  const auto head_end = answer.find("\r\n\r\n");
  if (head_end == std::string_view::npos) return false;
  const auto length = content_length(answer.substr(0, head_end + 2));
  return length && answer.size() >= head_end + 4 + std::min(*length, max_answer);
}

Result<HttpAnswer> parse_http_answer(std::string_view answer) {
  // "HTTP/1.1 204 No Content"
  if (answer.rfind("HTTP/1.", 0) != 0 || answer.size() < 12) {
    return make_error(Errc::invalid_frame, "not an HTTP answer");
  }
  // Three digits (RFC 9112 status-code), so "-12" or "+20" is no status.
  const std::string_view code = answer.substr(9, 3);
  if (!std::all_of(code.begin(), code.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return make_error(Errc::invalid_frame, "no status in the HTTP answer");
  }
  HttpAnswer result;
  result.status = (code[0] - '0') * 100 + (code[1] - '0') * 10 + (code[2] - '0');
  const auto head_end = answer.find("\r\n\r\n");
  if (head_end != std::string_view::npos) result.body = std::string(answer.substr(head_end + 4));
  return result;
}

}  // namespace rangekit::sinks
