#include "rangekit/core/udp.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>
#include <cerrno>

#include "rangekit/core/text.hpp"

namespace rangekit {
namespace {

Result<sockaddr_in> to_sockaddr(const Endpoint& endpoint) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(endpoint.port);
  const std::string host = endpoint.host == "localhost" ? "127.0.0.1" : endpoint.host;
  if (::inet_pton(AF_INET, host.c_str(), &address.sin_addr) != 1) {
    return make_error(Errc::bad_number, "'" + endpoint.host + "' is not an IPv4 address");
  }
  return address;
}

Endpoint from_sockaddr(const sockaddr_in& address) {
  char text[INET_ADDRSTRLEN] = {};
  ::inet_ntop(AF_INET, &address.sin_addr, text, sizeof text);
  return Endpoint{text, ntohs(address.sin_port)};
}

}  // namespace

Result<Endpoint> parse_endpoint(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) {
    return make_error(Errc::bad_number, "'" + text + "' is not HOST:PORT");
  }
  const auto port = text::parse_unsigned(std::string_view(text).substr(colon + 1), 5, 65535);
  if (!port) return make_error(Errc::bad_number, "'" + text + "': port must be 0-65535");
  Endpoint endpoint{text.substr(0, colon), static_cast<std::uint16_t>(*port)};
  if (auto address = to_sockaddr(endpoint); !address) return address.error();
  return endpoint;
}

Result<UdpSocket> UdpSocket::bind(const Endpoint& local) {
  auto address = to_sockaddr(local);
  if (!address) return address.error();
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) return make_error(Errc::io, errno_text("socket", errno));
  const int yes = 1;
  ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&address.value()), sizeof(sockaddr_in)) != 0) {
    const int error_number = errno;
    ::close(fd);
    return make_error(Errc::io, errno_text("cannot bind UDP " + local.to_string(), error_number));
  }
  return UdpSocket(fd);
}

UdpSocket::UdpSocket(UdpSocket&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }

UdpSocket& UdpSocket::operator=(UdpSocket&& other) noexcept {
  if (this != &other) {
    close();
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

UdpSocket::~UdpSocket() { close(); }

void UdpSocket::close() noexcept {
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
}

Status UdpSocket::send_to(Bytes datagram, const Endpoint& to) {
  if (fd_ < 0) return make_error(Errc::closed, "UDP socket is closed");
  auto address = to_sockaddr(to);
  if (!address) return address.error();
  const ssize_t sent = ::sendto(fd_, datagram.data(), datagram.size(), 0,
                                reinterpret_cast<const sockaddr*>(&address.value()), sizeof(sockaddr_in));
  if (sent < 0) return make_error(Errc::io, errno_text("UDP send to " + to.to_string(), errno));
  if (static_cast<std::size_t>(sent) != datagram.size()) return make_error(Errc::io, "UDP datagram sent in part");
  return ok_status();
}

Result<Datagram> UdpSocket::receive(std::span<std::uint8_t> out, std::chrono::milliseconds timeout) {
  if (fd_ < 0) return make_error(Errc::closed, "UDP socket is closed");
  pollfd waiter{fd_, POLLIN, 0};
  while (true) {
    const int ready = ::poll(&waiter, 1, static_cast<int>(timeout.count()));
    if (ready < 0 && errno == EINTR) continue;
    if (ready < 0) return make_error(Errc::io, errno_text("poll", errno));
    if (ready == 0)
      return make_error(Errc::timeout, "no UDP datagram within " + std::to_string(timeout.count()) + " ms");
    break;
  }
  sockaddr_in from{};
  socklen_t from_size = sizeof from;
  // MSG_TRUNC makes recvfrom report the real size, so an oversized datagram is caught.
  const ssize_t size =
      ::recvfrom(fd_, out.data(), out.size(), MSG_TRUNC, reinterpret_cast<sockaddr*>(&from), &from_size);
  if (size < 0) return make_error(Errc::io, errno_text("UDP receive", errno));
  if (static_cast<std::size_t>(size) > out.size()) {
    return make_error(Errc::overlong, "UDP datagram of " + std::to_string(size) + " bytes is larger than the " +
                                          std::to_string(out.size()) + "-byte buffer");
  }
  return Datagram{static_cast<std::size_t>(size), from_sockaddr(from)};
}

Endpoint UdpSocket::local_endpoint() const {
  sockaddr_in address{};
  socklen_t size = sizeof address;
  ::getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &size);
  return from_sockaddr(address);
}

Result<std::unique_ptr<FdTransport>> tcp_connect(const Endpoint& remote, std::chrono::milliseconds timeout) {
  auto address = to_sockaddr(remote);
  if (!address) return address.error();
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) return make_error(Errc::io, errno_text("socket", errno));
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address.value()), sizeof(sockaddr_in)) != 0 &&
      errno != EINPROGRESS) {
    const int error_number = errno;
    ::close(fd);
    return make_error(Errc::io, errno_text("cannot connect to " + remote.to_string(), error_number));
  }
  pollfd waiter{fd, POLLOUT, 0};
  const int ready = ::poll(&waiter, 1, static_cast<int>(timeout.count()));
  int socket_error = 0;
  socklen_t length = sizeof socket_error;
  ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &socket_error, &length);
  if (ready <= 0 || socket_error != 0) {
    ::close(fd);
    if (ready == 0) return make_error(Errc::timeout, "no TCP connection to " + remote.to_string() + " in time");
    return make_error(Errc::io, errno_text("cannot connect to " + remote.to_string(), socket_error));
  }
  return std::make_unique<FdTransport>(fd, "tcp " + remote.to_string());
}

}  // namespace rangekit
