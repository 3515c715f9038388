// UDP datagram sockets (LS5 Ethernet stream, section 10) and a TCP client
// stream. Tests use loopback addresses only.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "rangekit/core/fd_transport.hpp"

namespace rangekit {

struct Endpoint {
  std::string host;  // dotted IPv4 ("127.0.0.1") or "localhost"
  std::uint16_t port = 0;
  [[nodiscard]] std::string to_string() const { return host + ":" + std::to_string(port); }
};

// Parses "HOST:PORT".
Result<Endpoint> parse_endpoint(const std::string& text);

struct Datagram {
  std::size_t size = 0;
  Endpoint from;
};

class UdpSocket {
 public:
  // Binds to `local` (port 0 picks a free port).
  static Result<UdpSocket> bind(const Endpoint& local);
  UdpSocket(UdpSocket&& other) noexcept;
  UdpSocket& operator=(UdpSocket&& other) noexcept;
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;
  ~UdpSocket();

  Status send_to(Bytes datagram, const Endpoint& to);
  // Errc::timeout when nothing arrives in time. A datagram larger than `out` is
  // reported as Errc::overlong (its size is in the message), never silently cut.
  Result<Datagram> receive(std::span<std::uint8_t> out, std::chrono::milliseconds timeout);
  [[nodiscard]] Endpoint local_endpoint() const;
  void close() noexcept;

 private:
  explicit UdpSocket(int fd) : fd_(fd) {}
  int fd_ = -1;
};

// A TCP client connection as a byte-stream Transport.
Result<std::unique_ptr<FdTransport>> tcp_connect(const Endpoint& remote, std::chrono::milliseconds timeout);

}  // namespace rangekit
