#include "rangekit/ls5/logical_values.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <utility>

#include "ls5/messages.hpp"

namespace rangekit::ls5 {
namespace {

using L = LogicalValueId;
using K = ValueKind;

constexpr std::uint8_t period_bytes[] = {0x06, 0x07};
constexpr std::uint8_t absence_bytes[] = {0x09, 0x0A};
constexpr std::uint8_t analog_lower_bytes[] = {0x11, 0x12};
constexpr std::uint8_t analog_upper_bytes[] = {0x13, 0x14};
constexpr std::uint8_t out1_first_bytes[] = {0x16, 0x17};
constexpr std::uint8_t out1_second_bytes[] = {0x18, 0x19};
constexpr std::uint8_t out2_first_bytes[] = {0x1A, 0x1B};
constexpr std::uint8_t out2_second_bytes[] = {0x1C, 0x1D};
constexpr std::uint8_t exposure_bytes[] = {0x20, 0x21};
constexpr std::uint8_t analog_fixed_bytes[] = {0x23, 0x24};
constexpr std::uint8_t discrete_fixed_bytes[] = {0x25, 0x26};
constexpr std::uint8_t sensor_ip_bytes[] = {0x50, 0x51, 0x52, 0x53};
constexpr std::uint8_t gateway_bytes[] = {0x54, 0x55, 0x56, 0x57};
constexpr std::uint8_t mask_bytes[] = {0x58, 0x59, 0x5A, 0x5B};
constexpr std::uint8_t destination_ip_bytes[] = {0x5C, 0x5D, 0x5E, 0x5F};
constexpr std::uint8_t sensor_mac_bytes[] = {0x60, 0x61, 0x62, 0x63, 0x64, 0x65};
constexpr std::uint8_t destination_mac_bytes[] = {0x66, 0x67, 0x68, 0x69, 0x6A, 0x6B};
constexpr std::uint8_t destination_port_bytes[] = {0x6C, 0x6D};
constexpr std::uint8_t source_port_bytes[] = {0x6E, 0x6F};

constexpr std::uint64_t max_code = 50000;  // §8.10, §8.11: limits and swings are codes 0-50000

// Combined ranges: table 9.2 "For the parameter itself", and 0-50000 for codes (L5).
constexpr LogicalValueInfo values[] = {
    {L::measurement_period, "Measurement period", "period", period_bytes, 1, 0xFFFF, K::number, "ms", 0.1},
    {L::signal_absence_time, "Acceptable time of signal absence", "signal-absence-time", absence_bytes, 0, 0xFFFF,
     K::number, "ms", 1.0},
    {L::analog_lower_limit, "Lower limit of the analog output", "analog-lower", analog_lower_bytes, 0, max_code,
     K::number, "code", 1.0},
    {L::analog_upper_limit, "Upper limit of the analog output", "analog-upper", analog_upper_bytes, 0, max_code,
     K::number, "code", 1.0},
    {L::output1_first_swing, "First swing of the first discrete output", "output1-first-swing", out1_first_bytes, 0,
     max_code, K::number, "code", 1.0},
    {L::output1_second_swing, "Second swing of the first discrete output", "output1-second-swing", out1_second_bytes, 0,
     max_code, K::number, "code", 1.0},
    {L::output2_first_swing, "First swing of the second discrete output", "output2-first-swing", out2_first_bytes, 0,
     max_code, K::number, "code", 1.0},
    {L::output2_second_swing, "Second swing of the second discrete output", "output2-second-swing", out2_second_bytes,
     0, max_code, K::number, "code", 1.0},
    {L::max_exposure_time, "Maximum exposure time", "max-exposure", exposure_bytes, 1, 0xFFFF, K::number, "µs", 1.0},
    {L::analog_fixed_range, "Fixed range of the analog output", "analog-fixed-range", analog_fixed_bytes, 1, 0xFFFF,
     K::number, "code", 1.0},
    {L::discrete_fixed_range, "Fixed range of the discrete outputs", "discrete-fixed-range", discrete_fixed_bytes, 1,
     0xFFFF, K::number, "code", 1.0},
    {L::sensor_ip, "Sensor IP address", "ip-address", sensor_ip_bytes, 0, 0xFFFFFFFFULL, K::ipv4, "", 1.0},
    {L::gateway_ip, "Gateway IP address", "gateway", gateway_bytes, 0, 0xFFFFFFFFULL, K::ipv4, "", 1.0},
    {L::subnet_mask, "Subnetwork mask", "subnet-mask", mask_bytes, 0, 0xFFFFFFFFULL, K::ipv4, "", 1.0},
    {L::destination_ip, "Destination IP address", "destination-ip", destination_ip_bytes, 0, 0xFFFFFFFFULL, K::ipv4, "",
     1.0},
    {L::sensor_mac, "MAC address of the sensor", "mac-address", sensor_mac_bytes, 0, 0xFFFFFFFFFFFFULL, K::mac, "",
     1.0},
    {L::destination_mac, "Destination MAC address", "destination-mac", destination_mac_bytes, 0, 0xFFFFFFFFFFFFULL,
     K::mac, "", 1.0},
    {L::destination_port, "Destination port number", "destination-port", destination_port_bytes, 1, 0xFFFF, K::number,
     "", 1.0},
    {L::source_port, "Source port number", "source-port", source_port_bytes, 1, 0xFFFF, K::number, "", 1.0},
};

constexpr bool in_enum_order() {
  for (std::size_t i = 0; i < std::size(values); ++i) {
    if (static_cast<std::size_t>(values[i].id) != i + 1) return false;
  }
  return true;
}
static_assert(in_enum_order(), "logical value rows must follow LogicalValueId order (none excluded)");

std::string describe(const LogicalValueInfo& info) {
  return std::string(info.cli_name) + " (" + std::string(info.name) + ")";
}

// Bit position of a byte of `info` in the combined value, from table 9.2.
unsigned shift_of(std::uint8_t address) noexcept {
  const ParameterInfo* parameter = find_parameter(address);
  return parameter == nullptr ? 0U : 8U * parameter->significance;
}

Result<std::uint16_t> code_from_ms(double milliseconds, double unit_ms, std::uint16_t minimum, const char* what) {
  const double units = milliseconds / unit_ms;
  if (!std::isfinite(units) || units < minimum - 0.5 || units > 65535.5) {
    return make_error(Errc::out_of_range, std::string("LS5 ") + what + " " + std::to_string(milliseconds) +
                                              " ms is outside " + std::to_string(minimum * unit_ms) + "-" +
                                              std::to_string(65535 * unit_ms) + " ms");
  }
  const double rounded = std::round(units);
  if (std::fabs(units - rounded) > 1e-6) {
    return make_error(Errc::out_of_range, std::string("LS5 ") + what + " " + std::to_string(milliseconds) +
                                              " ms is not a whole number of " + std::to_string(unit_ms) + " ms");
  }
  return static_cast<std::uint16_t>(rounded);
}

}  // namespace

std::span<const LogicalValueInfo> logical_value_table() noexcept { return values; }

const LogicalValueInfo& logical_value_info(LogicalValueId id) noexcept {
  const auto index = static_cast<std::size_t>(id);
  return values[(index >= 1 && index <= std::size(values)) ? index - 1 : 0];
}

const LogicalValueInfo* find_logical_value_by_cli_name(std::string_view cli_name) noexcept {
  for (const LogicalValueInfo& info : values) {
    if (info.cli_name == cli_name) return &info;
  }
  return nullptr;
}

Result<std::uint64_t> combine_bytes(const LogicalValueInfo& info, std::span<const std::uint8_t> bytes) {
  if (bytes.size() != info.addresses.size()) {
    return make_error(Errc::wrong_form, "LS5 value " + describe(info) + " has " +
                                            std::to_string(info.addresses.size()) + " bytes, got " +
                                            std::to_string(bytes.size()));
  }
  std::uint64_t value = 0;
  for (std::size_t i = 0; i < bytes.size(); ++i) value |= std::uint64_t{bytes[i]} << shift_of(info.addresses[i]);
  return value;
}

Status check_logical_value(const LogicalValueInfo& info, std::uint64_t value) {
  if (value < info.min || value > info.max) {
    return make_error(Errc::out_of_range, "LS5 value " + describe(info) + " must be " + std::to_string(info.min) + "-" +
                                              std::to_string(info.max) + ", got " + std::to_string(value));
  }
  return ok_status();
}

Result<ParameterWrites> split_value(const LogicalValueInfo& info, std::uint64_t value) {
  Status in_range = check_logical_value(info, value);
  if (!in_range) return std::move(in_range).error();
  ParameterWrites writes;
  for (const std::uint8_t address : info.addresses) {
    const auto byte = static_cast<std::uint8_t>((value >> shift_of(address)) & 0xFFU);
    const ParameterInfo* parameter = find_parameter(address);
    if (parameter != nullptr && !value_in_spans(*parameter, byte)) {
      return make_error(Errc::out_of_range, "LS5 value " + describe(info) + " " + std::to_string(value) +
                                                " needs byte " + hex_byte(byte) + " at " + hex_byte(address) +
                                                ", which accepts " + describe_accepted_values(*parameter));
    }
    writes.items[writes.count++] = ParameterWrite{address, byte};
  }
  return writes;
}

namespace {
// Where a number's combined range comes from, for error messages.
const char* range_source(const LogicalValueInfo& info) {
  return info.max == max_code ? "limits and swings are codes 0-50000 over the range"
                              : "the parameter itself takes 0001-FFFF";
}

bool in_range(const LogicalValueInfo& info, std::uint64_t value) { return value >= info.min && value <= info.max; }

// Whether writing `first` keeps a two-byte number in range whatever in-range value it held
// before: for every byte the other address may hold in such a value, `first` with it must be in range.
bool first_write_always_in_range(const LogicalValueInfo& info, ParameterWrite first, std::uint8_t other_address) {
  const unsigned first_shift = shift_of(first.address);
  const std::uint64_t step = std::uint64_t{1} << first_shift;
  for (std::uint64_t other = 0; other <= 0xFF; ++other) {
    const std::uint64_t base = other << shift_of(other_address);
    // In-range values with this other byte exist when some x in 00-FF gives base + x * step in range.
    const std::uint64_t lowest_x = info.min > base ? (info.min - base + step - 1) / step : 0;
    const std::uint64_t highest_x = info.max >= base ? std::min<std::uint64_t>(0xFF, (info.max - base) / step) : 0;
    if (info.max < base || lowest_x > highest_x) continue;
    if (!in_range(info, base + std::uint64_t{first.value} * step)) return false;
  }
  return true;
}
}  // namespace

Status check_value_after_write(std::uint8_t address, std::uint8_t value, const ParameterByteReader& current) {
  const ParameterInfo* parameter = find_parameter(address);
  if (parameter == nullptr || parameter->part_of == LogicalValueId::none) return ok_status();
  const LogicalValueInfo& info = logical_value_info(parameter->part_of);
  if (info.kind != ValueKind::number) return ok_status();
  std::uint64_t combined = 0;
  std::string others;
  for (const std::uint8_t other : info.addresses) {
    const std::uint8_t byte = other == address ? value : current(other);
    combined |= std::uint64_t{byte} << shift_of(other);
    if (other != address) others += (others.empty() ? "" : ", ") + hex_byte(other) + " = " + hex_byte(byte);
  }
  if (in_range(info, combined)) return ok_status();
  return make_error(Errc::out_of_range, "LS5 parameter " + hex_byte(address) + " (" + std::string(parameter->name) +
                                            ") = " + hex_byte(value) + " with " + others + " makes " + describe(info) +
                                            " " + std::to_string(combined) + ", outside " + std::to_string(info.min) +
                                            "-" + std::to_string(info.max) + " (" + range_source(info) + ")");
}

ParameterWrites in_write_order(const LogicalValueInfo& info, ParameterWrites writes) {
  if (info.kind != ValueKind::number || writes.count != 2) return writes;
  if (!first_write_always_in_range(info, writes.items[0], writes.items[1].address)) {
    std::swap(writes.items[0], writes.items[1]);
  }
  return writes;
}

Result<ParameterWrites> split_value_in_write_order(const LogicalValueInfo& info, std::uint64_t value) {
  auto writes = split_value(info, value);
  if (!writes) return writes;
  return in_write_order(info, *writes);
}

std::uint64_t default_value(const LogicalValueInfo& info, std::uint32_t serial_number) noexcept {
  std::uint64_t value = 0;
  for (const std::uint8_t address : info.addresses) {
    const ParameterInfo* parameter = find_parameter(address);
    if (parameter != nullptr) value |= std::uint64_t{default_byte(*parameter, serial_number)} << shift_of(address);
  }
  return value;
}

Result<std::uint16_t> period_code_from_ms(double milliseconds) {
  return code_from_ms(milliseconds, 0.1, 1, "measurement period");
}

double period_ms(std::uint16_t code) noexcept { return code / 10.0; }

Result<std::uint16_t> signal_absence_code_from_ms(double milliseconds) {
  return code_from_ms(milliseconds, 1.0, 0, "acceptable time of signal absence");
}

std::uint64_t default_sensor_mac(std::uint32_t serial_number) noexcept {
  return default_value(logical_value_info(LogicalValueId::sensor_mac), serial_number);
}

std::string format_ipv4(std::uint32_t address) {
  return std::to_string((address >> 24U) & 0xFFU) + "." + std::to_string((address >> 16U) & 0xFFU) + "." +
         std::to_string((address >> 8U) & 0xFFU) + "." + std::to_string(address & 0xFFU);
}

std::string format_mac(std::uint64_t address) {
  std::string text;
  for (int octet = 5; octet >= 0; --octet) {
    text += hex_byte(static_cast<std::uint8_t>((address >> (8U * static_cast<unsigned>(octet))) & 0xFFU));
    if (octet > 0) text += ':';
  }
  return text;
}

std::string format_value(const LogicalValueInfo& info, std::uint64_t value) {
  switch (info.kind) {
    case ValueKind::ipv4:
      return format_ipv4(static_cast<std::uint32_t>(value));
    case ValueKind::mac:
      return format_mac(value);
    case ValueKind::number:
      break;
  }
  std::string text;
  if (info.scale == 1.0) {
    text = std::to_string(value);
  } else {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.1f", static_cast<double>(value) * info.scale);
    text = buffer;
  }
  if (!info.unit.empty() && info.unit != "code") text += " " + std::string(info.unit);
  return text;
}

}  // namespace rangekit::ls5
