// Values built from several table 9.2 bytes (conformance L5): the period, τ, the
// analog limits, the swings, exposure, fixed ranges, IP and MAC addresses, ports.
// Bytes are written one at a time; these helpers split and combine them.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>

#include "rangekit/core/result.hpp"
#include "rangekit/ls5/parameters.hpp"

namespace rangekit::ls5 {

enum class ValueKind : std::uint8_t { number, ipv4, mac };

struct LogicalValueInfo {
  LogicalValueId id;
  std::string_view name;
  std::string_view cli_name;                // e.g. "period", "analog-lower", "ip-address"
  std::span<const std::uint8_t> addresses;  // in table order (ascending address)
  std::uint64_t min;                        // combined range, raw units
  std::uint64_t max;
  ValueKind kind;
  std::string_view unit;  // what one raw unit times `scale` is in: "ms", "µs", "code", ""
  double scale;           // raw × scale = amount in `unit` (period: 0.1)
};

std::span<const LogicalValueInfo> logical_value_table() noexcept;
const LogicalValueInfo& logical_value_info(LogicalValueId id) noexcept;  // id != none
const LogicalValueInfo* find_logical_value_by_cli_name(std::string_view cli_name) noexcept;

struct ParameterWrite {
  std::uint8_t address;
  std::uint8_t value;
  friend constexpr bool operator==(const ParameterWrite&, const ParameterWrite&) = default;
};

// Up to six byte writes (a MAC address), in table order.
struct ParameterWrites {
  std::array<ParameterWrite, 6> items{};
  std::size_t count = 0;
  [[nodiscard]] std::span<const ParameterWrite> view() const noexcept { return {items.data(), count}; }
};

// Combined value from its bytes, given in the order of info.addresses.
Result<std::uint64_t> combine_bytes(const LogicalValueInfo& info, std::span<const std::uint8_t> bytes);
// The byte writes that set `value`, in table order; checks the combined range and every byte's
// accepted values. To send them, use split_value_in_write_order.
Result<ParameterWrites> split_value(const LogicalValueInfo& info, std::uint64_t value);
Status check_logical_value(const LogicalValueInfo& info, std::uint64_t value);

// A byte the sensor holds now (its RAM, or what the host last read or wrote there).
using ParameterByteReader = std::function<std::uint8_t(std::uint8_t address)>;

// Conformance L50: a W of one byte must leave the number it is part of in its combined range
// (codes 0-50000, §8.10/§8.11; period, exposure, fixed ranges and ports 0001-FFFF, table 9.2),
// the number's other bytes as `current` reads them. Bytes of no number (single parameters, IP and
// MAC octets) pass. The byte's own accepted values are check_parameter_byte's job.
Status check_value_after_write(std::uint8_t address, std::uint8_t value, const ParameterByteReader& current);

// The writes of split_value in an order that keeps every intermediate value in range whatever
// in-range value the bytes held before (L50), so the sensor accepts each one: table order (low
// byte first; ports high byte first), except that the other byte goes first when the first could
// leave the value out of range: a code whose low byte is above 50 (the high byte may still be C3),
// a 0001-FFFF value whose first-written byte is 00 (the other may still be 00).
Result<ParameterWrites> split_value_in_write_order(const LogicalValueInfo& info, std::uint64_t value);
// The same order for writes already split (all part of `info`, e.g. raw bytes given
// by a user): the two writes of a number swapped when table order is not safe (L50, L62).
ParameterWrites in_write_order(const LogicalValueInfo& info, ParameterWrites writes);
// The value the table's default bytes make (MAC from the serial number).
std::uint64_t default_value(const LogicalValueInfo& info, std::uint32_t serial_number) noexcept;

// Table 9.2 unit conversions. Each rejects values that are not a whole number of
// units or do not fit (conformance L21).
Result<std::uint16_t> period_code_from_ms(double milliseconds);  // t = code × 0.1 ms, code 0001-FFFF
double period_ms(std::uint16_t code) noexcept;
Result<std::uint16_t> signal_absence_code_from_ms(double milliseconds);  // τ = code × 1 ms, code 0000-FFFF

// Default sensor MAC 1E:30:6C:A2:XX:YY (table 9.2, §10).
std::uint64_t default_sensor_mac(std::uint32_t serial_number) noexcept;

// Text for tables and the CLI: "10.0 ms", "50000", "192.168.0.3", "1E:30:6C:A2:00:9D".
std::string format_value(const LogicalValueInfo& info, std::uint64_t value);
std::string format_ipv4(std::uint32_t address);
std::string format_mac(std::uint64_t address);

}  // namespace rangekit::ls5
