// The Modbus TCP listener: one asio event loop, a bounded number of connections, each read
// into a fixed buffer, framed by scan_mbap_frame and answered by answer_request.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "modbus/request.hpp"
#include "rangekit/core/address_range.hpp"
#include "rangekit/core/udp.hpp"

namespace rangekit::modbus {

struct ServerCounters {
  std::atomic<std::uint64_t> clients{0};
  std::atomic<std::uint64_t> requests{0};
  std::atomic<std::uint64_t> exceptions{0};
  std::atomic<std::uint64_t> refused{0};
  std::atomic<std::uint64_t> malformed{0};
};

struct ServerSettings {
  Endpoint listen;
  std::vector<AddressRange> allow;  // beyond loopback
  std::size_t max_clients = 64;
  std::chrono::milliseconds idle_timeout{60000};
  std::function<void(const std::string&)> log;
};

class Server {
 public:
  // Binds; serving begins with run(). An address beyond loopback without an allow list is refused.
  static Result<std::unique_ptr<Server>> bind(ServerSettings settings, UnitTable& units, ServerCounters& counters);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;
  void run();   // the event loop, until stop()
  void stop();  // from another thread: closes the listener and every connection
  [[nodiscard]] Endpoint local_endpoint() const;

  struct Impl;

 private:
  explicit Server(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace rangekit::modbus
