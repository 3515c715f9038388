// Typed meanings of the enumerated table 9.2 parameters: baud codes, byte
// formats, triggering, latching, pre-filter, result type, priority.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "rangekit/ls5/version.hpp"

namespace rangekit::ls5 {

// Table 9.2 default of the network address (§8.1 "The initial address set at the manufacturer is 01").
inline constexpr std::uint8_t default_network_address = 0x01;

// Parameter addresses the codec and formulas refer to by name.
namespace address {
inline constexpr std::uint8_t network_address = 0x01;
inline constexpr std::uint8_t power_on_state = 0x02;
inline constexpr std::uint8_t analog_enabled = 0x03;
inline constexpr std::uint8_t byte_format = 0x04;
inline constexpr std::uint8_t baud_rate = 0x05;
inline constexpr std::uint8_t period_low = 0x06;
inline constexpr std::uint8_t period_high = 0x07;
inline constexpr std::uint8_t thinning = 0x08;
inline constexpr std::uint8_t signal_absence_low = 0x09;
inline constexpr std::uint8_t signal_absence_high = 0x0A;
inline constexpr std::uint8_t pre_filter = 0x0B;
inline constexpr std::uint8_t averaging_points = 0x0C;
inline constexpr std::uint8_t median_points = 0x0D;
inline constexpr std::uint8_t result_type = 0x0E;
inline constexpr std::uint8_t analog_lower_low = 0x11;
inline constexpr std::uint8_t analog_lower_high = 0x12;
inline constexpr std::uint8_t analog_upper_low = 0x13;
inline constexpr std::uint8_t analog_upper_high = 0x14;
inline constexpr std::uint8_t discrete_outputs = 0x15;
inline constexpr std::uint8_t output1_first_swing_low = 0x16;
inline constexpr std::uint8_t output1_first_swing_high = 0x17;
inline constexpr std::uint8_t output1_second_swing_low = 0x18;
inline constexpr std::uint8_t output1_second_swing_high = 0x19;
inline constexpr std::uint8_t output2_first_swing_low = 0x1A;
inline constexpr std::uint8_t output2_first_swing_high = 0x1B;
inline constexpr std::uint8_t output2_second_swing_low = 0x1C;
inline constexpr std::uint8_t output2_second_swing_high = 0x1D;
inline constexpr std::uint8_t triggering = 0x1E;
inline constexpr std::uint8_t latching = 0x1F;
inline constexpr std::uint8_t exposure_low = 0x20;
inline constexpr std::uint8_t exposure_high = 0x21;
inline constexpr std::uint8_t priority = 0x22;
inline constexpr std::uint8_t analog_fixed_range_low = 0x23;
inline constexpr std::uint8_t analog_fixed_range_high = 0x24;
inline constexpr std::uint8_t discrete_fixed_range_low = 0x25;
inline constexpr std::uint8_t discrete_fixed_range_high = 0x26;
inline constexpr std::uint8_t destination_ip_first = 0x5C;   // 5C-5F: the first octet first
inline constexpr std::uint8_t destination_port_high = 0x6C;  // table 9.2 lists the ports high byte first
inline constexpr std::uint8_t destination_port_low = 0x6D;
inline constexpr std::uint8_t source_port_high = 0x6E;
inline constexpr std::uint8_t source_port_low = 0x6F;
inline constexpr std::uint8_t udp_auto_stream = 0x70;
}  // namespace address

// Parameter 05 (table 9.2).
struct BaudRateInfo {
  std::uint8_t code;
  std::uint32_t baud;
  FirmwareVersion since;  // 06-08 need LS5.6.0 (note 2)
};
std::span<const BaudRateInfo> baud_rate_table() noexcept;
std::optional<std::uint32_t> baud_rate_from_code(std::uint8_t code) noexcept;
std::optional<std::uint8_t> baud_code_from_rate(std::uint32_t baud) noexcept;

// Parameter 04 (§8.3, table 9.2). "Parity control" is even parity, "imparity
// control" odd parity (conformance L22).
enum class Parity : std::uint8_t { none, even, odd };
struct ByteFormat {
  std::uint8_t code;
  Parity parity;
  std::uint8_t stop_bits;
  std::string_view name;  // "8N1", "8E1", ...
};
std::span<const ByteFormat> byte_format_table() noexcept;
std::optional<ByteFormat> byte_format_from_code(std::uint8_t code) noexcept;

enum class Triggering : std::uint8_t { timer = 0x00, sync_input = 0x01 };     // parameter 1E
enum class PreFilter : std::uint8_t { averaging = 0x00, median = 0x01 };      // parameter 0B
enum class ResultType : std::uint8_t { pure = 0x00, derivative = 0x01 };      // parameter 0E
enum class Priority : std::uint8_t { frequency = 0x00, sensitivity = 0x01 };  // parameter 22

// Parameter 1F (table 9.2, §8.13, §8.14).
enum class LatchingMode : std::uint8_t {
  off = 0x00,
  latch_only = 0x01,
  analog_limits = 0x02,
  analog_limits_to_rom = 0x03,
  output1_limits = 0x04,
  output1_limits_to_rom = 0x05,
  output2_limits = 0x06,
  output2_limits_to_rom = 0x07,
  output1_lower_output2_upper = 0x08,
  output1_lower_output2_upper_to_rom = 0x09,
};
std::optional<LatchingMode> latching_mode_from_byte(std::uint8_t value) noexcept;
// Odd recalculating modes also write the new limits to non-volatile memory.
bool latching_writes_rom(LatchingMode mode) noexcept;

}  // namespace rangekit::ls5
