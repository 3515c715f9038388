// A Unix-domain socket that takes one JSON object per line and answers each
// with one JSON line: how tests and users steer a running emulator (move a
// target, inject faults, advance a virtual clock, read the analog outputs).
#pragma once

#include <poll.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "rangekit/core/result.hpp"

namespace rangekit {

class ControlSocket {
 public:
  using Handler = std::function<nlohmann::json(const nlohmann::json& request)>;

  // Listens at `path` (mode 0600 whatever the umask); fails if something already
  // exists there. Removes the socket file when destroyed.
  static Result<std::unique_ptr<ControlSocket>> listen(const std::string& path);
  ~ControlSocket();
  ControlSocket(const ControlSocket&) = delete;
  ControlSocket& operator=(const ControlSocket&) = delete;

  // Appends the file descriptors to poll for input (listener and clients), POLLIN.
  void add_poll_fds(std::vector<pollfd>& fds) const;
  // Accepts new clients and answers every complete line that arrived. A line
  // that is not a JSON object (invalid UTF-8 included) gets {"error": "..."};
  // nothing throws out of here.
  void service(const Handler& handler);
  [[nodiscard]] const std::string& path() const noexcept { return path_; }
  // The most bytes ever held for one peer's unanswered request: reading stops one byte past
  // 64 KiB, where the request is refused and the connection closed.
  [[nodiscard]] std::size_t peak_pending() const noexcept { return peak_pending_; }

 private:
  struct Client {
    int fd;
    std::string pending;
  };
  ControlSocket(int fd, std::string path) : listener_(fd), path_(std::move(path)) {}
  static void close_client(Client& client);
  static void answer_lines(const Handler& handler, Client& client);
  int listener_;
  std::string path_;
  std::vector<Client> clients_;
  std::size_t peak_pending_ = 0;
};

// Client side, for tests and the CLI: one request, one reply.
class ControlClient {
 public:
  static Result<ControlClient> connect(const std::string& path);
  ControlClient(ControlClient&& other) noexcept;
  ControlClient& operator=(ControlClient&& other) noexcept;
  ControlClient(const ControlClient&) = delete;
  ControlClient& operator=(const ControlClient&) = delete;
  ~ControlClient();
  Result<nlohmann::json> request(const nlohmann::json& request, int timeout_ms = 5000);
  // Sends `line` as it is (a newline is added), for tests of what a malformed line gets.
  Result<nlohmann::json> request_line(const std::string& line, int timeout_ms = 5000);

 private:
  explicit ControlClient(int fd) : fd_(fd) {}
  int fd_ = -1;
  std::string pending_;
};

// The reply line (without '\n') to one request line: what the socket sends back. Never
// throws; a line that is not a JSON object or not UTF-8 gets {"error": ...} (fuzzed
// by fuzz/control_fuzz.cpp).
std::string answer_control_line(const ControlSocket::Handler& handler, const std::string& line);

// A number field of a control request checked against the range it means
// ("noise: 'drop_rate' must be a number within 0 .. 1, not 2"). Without the
// key the result is `fallback`, or an error when there is none. Errc::out_of_range.
Result<double> control_number(const nlohmann::json& request, std::string_view key, double min, double max,
                              std::optional<double> fallback = std::nullopt);

// JSON text of `value` with any invalid UTF-8 replaced (U+FFFD) instead of throwing.
std::string safe_dump(const nlohmann::json& value);

}  // namespace rangekit
