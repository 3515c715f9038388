#include "rangekit/ls5/settings.hpp"

#include <array>

namespace rangekit::ls5 {
namespace {

// Table 9.2, parameter 05.
constexpr std::array<BaudRateInfo, 8> baud_rates{{
    {0x01, 9600, any_firmware},
    {0x02, 19200, any_firmware},
    {0x03, 38400, any_firmware},
    {0x04, 57600, any_firmware},
    {0x05, 115200, any_firmware},
    {0x06, 230400, firmware_6_0},
    {0x07, 460800, firmware_6_0},
    {0x08, 921600, firmware_6_0},
}};

// Table 9.2, parameter 04.
constexpr std::array<ByteFormat, 6> byte_formats{{
    {0x00, Parity::none, 1, "8N1"},
    {0x01, Parity::even, 1, "8E1"},
    {0x02, Parity::odd, 1, "8O1"},
    {0x03, Parity::none, 2, "8N2"},
    {0x04, Parity::even, 2, "8E2"},
    {0x05, Parity::odd, 2, "8O2"},
}};

}  // namespace

std::span<const BaudRateInfo> baud_rate_table() noexcept { return baud_rates; }

std::optional<std::uint32_t> baud_rate_from_code(std::uint8_t code) noexcept {
  for (const BaudRateInfo& rate : baud_rates) {
    if (rate.code == code) return rate.baud;
  }
  return std::nullopt;
}

std::optional<std::uint8_t> baud_code_from_rate(std::uint32_t baud) noexcept {
  for (const BaudRateInfo& rate : baud_rates) {
    if (rate.baud == baud) return rate.code;
  }
  return std::nullopt;
}

std::span<const ByteFormat> byte_format_table() noexcept { return byte_formats; }

std::optional<ByteFormat> byte_format_from_code(std::uint8_t code) noexcept {
  if (code >= byte_formats.size()) return std::nullopt;
  return byte_formats[code];
}

std::optional<LatchingMode> latching_mode_from_byte(std::uint8_t value) noexcept {
  if (value > static_cast<std::uint8_t>(LatchingMode::output1_lower_output2_upper_to_rom)) return std::nullopt;
  return static_cast<LatchingMode>(value);
}

bool latching_writes_rom(LatchingMode mode) noexcept {
  switch (mode) {
    case LatchingMode::analog_limits_to_rom:
    case LatchingMode::output1_limits_to_rom:
    case LatchingMode::output2_limits_to_rom:
    case LatchingMode::output1_lower_output2_upper_to_rom:
      return true;
    default:
      return false;
  }
}

}  // namespace rangekit::ls5
