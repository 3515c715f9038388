// The byte-stream transport interface protocol logic talks through: a serial
// port, a pseudo-terminal, a TCP stream or an in-memory loopback pair all look
// the same to a driver or an emulator (as libmodbus' backends do).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "rangekit/core/framer.hpp"
#include "rangekit/core/result.hpp"

namespace rangekit {

class Transport {
 public:
  Transport() = default;
  Transport(const Transport&) = delete;
  Transport& operator=(const Transport&) = delete;
  virtual ~Transport() = default;

  // Writes every byte or fails (Errc::closed when the other end is gone, Errc::io otherwise).
  virtual Status write_all(Bytes data) = 0;
  // Waits up to `timeout` for at least one byte, then returns what is available
  // (at most out.size()). Errc::timeout when nothing came, Errc::closed when the
  // other end is gone and nothing is left to read.
  virtual Result<std::size_t> read_some(std::span<std::uint8_t> out, std::chrono::milliseconds timeout) = 0;
  // Closes this end; later calls fail with Errc::closed. Safe to call twice.
  virtual void close() noexcept = 0;
  // Human-readable name for messages ("/dev/ttyUSB0", "loopback A", ...).
  [[nodiscard]] virtual std::string name() const = 0;
};

using TransportPtr = std::unique_ptr<Transport>;

}  // namespace rangekit
