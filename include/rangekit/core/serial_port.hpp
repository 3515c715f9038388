// Serial ports (USB adapters, RS-232, RS-485 converters) and pseudo-terminals
// through termios. Raw mode, 8 data bits, no flow control.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "rangekit/core/fd_transport.hpp"
#include "rangekit/core/transport.hpp"

namespace rangekit {

enum class Parity { none, even, odd };

struct SerialSettings {
  std::uint32_t baud = 115200;
  Parity parity = Parity::none;
  int stop_bits = 1;  // 1 or 2

  // Bits on the wire per byte: start + 8 data + parity + stop.
  [[nodiscard]] int bits_per_byte() const noexcept { return 1 + 8 + (parity == Parity::none ? 0 : 1) + stop_bits; }
  bool operator==(const SerialSettings&) const = default;
};

std::string describe(const SerialSettings& settings);  // "115200 8N1"

// Applies `settings` to an open terminal fd (raw mode). Errc::unsupported for a
// baud the system cannot set.
Status apply_serial_settings(int fd, const SerialSettings& settings);
// Reads the speed, parity and stop bits currently set on a terminal fd. On a
// pty both ends share one termios, so the master sees what the slave's user set.
Result<SerialSettings> read_serial_settings(int fd);

class SerialPort final : public FdTransport {
 public:
  static Result<std::unique_ptr<SerialPort>> open(const std::string& path, const SerialSettings& settings);
  Status reconfigure(const SerialSettings& settings);
  [[nodiscard]] const SerialSettings& settings() const noexcept { return settings_; }

 private:
  SerialPort(int fd, std::string path, SerialSettings settings)
      : FdTransport(fd, std::move(path)), settings_(settings) {}
  SerialSettings settings_;
};

// A serial port or pty opened as a driver's link. Any failure to open (missing path, no
// permission, not a terminal, a speed the system cannot set) is Errc::io naming the port
// once: the one opener of the CLI, the service and the Python package.
Result<TransportPtr> open_serial_link(const std::string& path, const SerialSettings& settings);

}  // namespace rangekit
