// Live measurement sources on serial ports, set up the way `demo` and `capture`
// need them: the port opened, the driver connected (with reconnect on the same
// path and baud) and the stream started, returned as one SampleSource.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/core/transport.hpp"

namespace rangekit::cli {

// Opens a serial port or pty, the one way every subcommand does. Any failure to
// open (missing path, no permission, not a terminal, a speed the system cannot set)
// is Errc::io, exit 4 (docs/cli.md), with the port named once in the message.
Result<TransportPtr> open_port(const std::string& path, const SerialSettings& settings);
// 8N1 at `baud`, the ULS's only byte format (§9) and the LS5's default.
Result<TransportPtr> open_serial(const std::string& path, std::uint32_t baud);
// The reopen function a driver reconnects with: the same path and line settings.
std::function<Result<TransportPtr>()> reopen_port(const std::string& path, const SerialSettings& settings);

struct UlsSourceOptions {
  std::string port;
  std::uint32_t baud = 115200;
  std::optional<std::uint8_t> address;  // RS-485 '#a' protocol
  std::string label;                    // Sample::source; default the port path
};
Result<SampleSourcePtr> start_uls_source(const UlsSourceOptions& options);

struct Ls5SourceOptions {
  std::string port;
  std::uint32_t baud = 115200;
  std::uint8_t address = 0x01;
  std::optional<std::uint8_t> thinning;  // n of §8.4; the sensor's setting when empty
};
Result<SampleSourcePtr> start_ls5_source(const Ls5SourceOptions& options);

}  // namespace rangekit::cli
