// Live measurement sources on serial ports, set up the way `demo` and `capture`
// need them: the port opened, the driver connected (with reconnect on the same
// path and baud) and the stream started, returned as one SampleSource.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/core/transport.hpp"

namespace rangekit::cli {

Result<TransportPtr> open_serial(const std::string& path, std::uint32_t baud);

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
