// A Transport over a POSIX file descriptor (serial device, pty master, TCP socket).
#pragma once

#include "rangekit/core/transport.hpp"

namespace rangekit {

class FdTransport : public Transport {
 public:
  // Takes ownership of `fd` (closed by close() and the destructor).
  FdTransport(int fd, std::string name);
  ~FdTransport() override;

  Status write_all(Bytes data) override;
  Result<std::size_t> read_some(std::span<std::uint8_t> out, std::chrono::milliseconds timeout) override;
  void close() noexcept override;
  [[nodiscard]] std::string name() const override { return name_; }
  [[nodiscard]] int native_handle() const noexcept { return fd_; }

 private:
  void close_descriptor() noexcept;  // non-virtual: also used by the destructor
  int fd_;
  std::string name_;
};

// "what: strerror(errno)" for messages.
std::string errno_text(const std::string& what, int error_number);

}  // namespace rangekit
