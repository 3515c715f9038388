// A small HTTP/1.1 client over POSIX sockets for the web tests (loopback only):
// one request per connection, and a Server-Sent Events reader that parses events
// as they arrive, with a deadline as a safety net (never as synchronisation).
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace web_test {

inline int connect_to(std::uint16_t port, int receive_buffer = 0) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (receive_buffer > 0) ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

inline bool send_all(int fd, const std::string& text) {
  std::size_t sent = 0;
  while (sent < text.size()) {
    const ssize_t n = ::send(fd, text.data() + sent, text.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) return false;
    sent += static_cast<std::size_t>(n);
  }
  return true;
}

// Reads what is there within `wait`; false at end of stream or error.
inline bool read_some(int fd, std::string& into, std::chrono::milliseconds wait) {
  pollfd entry{fd, POLLIN, 0};
  if (::poll(&entry, 1, static_cast<int>(wait.count())) <= 0) return true;
  char buffer[65536];
  const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
  if (n <= 0) return false;
  into.append(buffer, static_cast<std::size_t>(n));
  return true;
}

struct Reply {
  int status = 0;
  std::map<std::string, std::string> headers;  // lower-case names
  std::string body;
};

inline std::string request_text(const std::string& method, const std::string& target, const std::string& body,
                                const std::vector<std::string>& headers, std::uint16_t port) {
  std::string text =
      method + " " + target + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\nConnection: close\r\n";
  for (const auto& header : headers) text += header + "\r\n";
  if (!body.empty() || method == "PATCH" || method == "POST") {
    text += "Content-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) + "\r\n";
  }
  return text + "\r\n" + body;
}

// One request on its own connection; `raw` replaces the generated request text.
inline Reply http(std::uint16_t port, const std::string& method, const std::string& target,
                  const std::string& body = {}, const std::vector<std::string>& headers = {},
                  const std::string& raw = {}) {
  Reply reply;
  const int fd = connect_to(port);
  if (fd < 0) return reply;
  send_all(fd, raw.empty() ? request_text(method, target, body, headers, port) : raw);
  std::string all;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < deadline && read_some(fd, all, std::chrono::milliseconds(200))) {
  }
  ::close(fd);
  const auto end_of_head = all.find("\r\n\r\n");
  if (all.rfind("HTTP/1.1 ", 0) != 0 || end_of_head == std::string::npos) return reply;
  reply.status = std::stoi(all.substr(9, 3));
  std::size_t line = all.find("\r\n") + 2;
  while (line < end_of_head) {
    const std::size_t next = all.find("\r\n", line);
    const std::string header = all.substr(line, next - line);
    const std::size_t colon = header.find(':');
    std::string name = header.substr(0, colon);
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    reply.headers[name] = header.substr(colon + 2);
    line = next + 2;
  }
  reply.body = all.substr(end_of_head + 4);
  return reply;
}

struct Event {
  std::uint64_t id = 0;
  std::string type;
  std::string data;
};

// An open SSE stream: GET sent at construction; events parsed as they come.
class EventReader {
 public:
  EventReader(std::uint16_t port, const std::string& target, const std::vector<std::string>& headers = {},
              int receive_buffer = 0)
      : fd_(connect_to(port, receive_buffer)) {
    if (fd_ >= 0) send_all(fd_, request_text("GET", target, {}, headers, port));
  }
  ~EventReader() { close(); }
  EventReader(const EventReader&) = delete;
  EventReader& operator=(const EventReader&) = delete;
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

  // Reads until `done(event)` is true for a new event or the deadline passes; false on timeout or close.
  template <class Done>
  bool read_until(Done done, std::chrono::seconds limit = std::chrono::seconds(30)) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    for (;;) {
      while (parse_one()) {
        if (done(events.back())) return true;
      }
      if (std::chrono::steady_clock::now() >= deadline) return false;
      if (!read_some(fd_, buffer_, std::chrono::milliseconds(100))) {
        open_ = false;
        while (parse_one()) {
          if (done(events.back())) return true;
        }
        return false;
      }
    }
  }
  // Reads once what arrived within `wait` and parses it; the number of new events.
  std::size_t pump(std::chrono::milliseconds wait) {
    const std::size_t before = events.size();
    if (!read_some(fd_, buffer_, wait)) open_ = false;
    while (parse_one()) {
    }
    return events.size() - before;
  }
  // Reads until the server closes the stream (or the deadline).
  bool read_to_end(std::chrono::seconds limit) {
    read_until([](const Event&) { return false; }, limit);
    return !open_;
  }

  int status() const { return buffer_.rfind("HTTP/1.1 ", 0) == 0 ? std::stoi(buffer_.substr(9, 3)) : status_; }
  std::vector<Event> events;

 private:
  bool parse_one() {
    if (!head_done_) {
      const auto end = buffer_.find("\r\n\r\n");
      if (end == std::string::npos) return false;
      status_ = buffer_.rfind("HTTP/1.1 ", 0) == 0 ? std::stoi(buffer_.substr(9, 3)) : 0;
      buffer_.erase(0, end + 4);
      head_done_ = true;
    }
    for (;;) {
      const auto end = buffer_.find("\n\n");
      if (end == std::string::npos) return false;
      const std::string block = buffer_.substr(0, end);
      buffer_.erase(0, end + 2);
      Event event;
      std::size_t start = 0;
      while (start < block.size()) {
        std::size_t stop = block.find('\n', start);
        if (stop == std::string::npos) stop = block.size();
        const std::string line = block.substr(start, stop - start);
        if (line.rfind("id: ", 0) == 0) event.id = std::stoull(line.substr(4));
        if (line.rfind("event: ", 0) == 0) event.type = line.substr(7);
        if (line.rfind("data: ", 0) == 0) event.data = line.substr(6);
        start = stop + 1;
      }
      if (event.type.empty()) continue;  // a comment (": keepalive")
      events.push_back(event);
      return true;
    }
  }

  int fd_ = -1;
  std::string buffer_;
  bool head_done_ = false;
  bool open_ = true;
  int status_ = 0;
};

}  // namespace web_test
