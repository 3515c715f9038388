// Table 9.2 of the LS5 manual as data: every parameter byte the sensor keeps,
// what it accepts, its default, which firmware brought it, and which multi-byte
// value it is part of. Multi-byte values themselves are in logical_values.hpp.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "rangekit/core/result.hpp"
#include "rangekit/ls5/version.hpp"

namespace rangekit::ls5 {

// The values that are built from several parameter bytes (conformance L5).
enum class LogicalValueId : std::uint8_t {
  none,                  // the byte is a parameter on its own
  measurement_period,    // 06/07, 0.1 ms units
  signal_absence_time,   // 09/0A, τ in ms
  analog_lower_limit,    // 11/12, code 0-50000
  analog_upper_limit,    // 13/14
  output1_first_swing,   // 16/17
  output1_second_swing,  // 18/19
  output2_first_swing,   // 1A/1B
  output2_second_swing,  // 1C/1D
  max_exposure_time,     // 20/21, µs
  analog_fixed_range,    // 23/24, code
  discrete_fixed_range,  // 25/26, code
  sensor_ip,             // 50-53
  gateway_ip,            // 54-57
  subnet_mask,           // 58-5B
  destination_ip,        // 5C-5F
  sensor_mac,            // 60-65
  destination_mac,       // 66-6B
  destination_port,      // 6C/6D, high byte first
  source_port,           // 6E/6F, high byte first
};

// A run of accepted byte values first, first+step, ..., last, available from `since`.
struct ValueSpan {
  std::uint8_t first;
  std::uint8_t last;
  std::uint8_t step = 1;
  FirmwareVersion since = any_firmware;
};

// A named value of an enumerated parameter (baud codes, latching modes, ...).
struct NamedValue {
  std::uint8_t value;
  std::string_view cli_name;  // e.g. "115200", "8N1", "median"
  std::string_view meaning;   // as table 9.2 describes it
};

enum class DefaultSource : std::uint8_t {
  fixed,             // default_value below
  serial_high_byte,  // MAC byte 64 "XX": high byte of the serial number (conformance L20)
  serial_low_byte,   // MAC byte 65 "YY": low byte of the serial number
};

// How a byte sits in its value: on its own, low/high byte of a 16-bit value, or one
// octet of an IP/MAC address (octet 0 is the first one written, 192 of 192.168.0.3).
enum class ByteRole : std::uint8_t { whole, low_byte, high_byte, octet };

struct ParameterInfo {
  std::uint8_t address;
  std::string_view name;      // readable, from table 9.2
  std::string_view cli_name;  // e.g. "baud-rate", "period.low", "ip-address.0"
  std::span<const ValueSpan> accepted;
  std::uint8_t default_value;
  DefaultSource default_source = DefaultSource::fixed;
  LogicalValueId part_of = LogicalValueId::none;
  std::uint8_t significance = 0;  // weight of the byte in its value: value += byte << (8 × significance)
  FirmwareVersion since = any_firmware;
  bool ethernet_only = false;
  std::span<const NamedValue> named_values{};
};

// What a sensor offers: the firmware it reported and whether it has Ethernet.
struct SensorModel {
  FirmwareVersion firmware = any_firmware;
  bool ethernet = false;
};

std::span<const ParameterInfo> parameter_table() noexcept;
const ParameterInfo* find_parameter(std::uint8_t address) noexcept;
const ParameterInfo* find_parameter_by_cli_name(std::string_view cli_name) noexcept;

ByteRole byte_role(const ParameterInfo& parameter) noexcept;
// Octet index for ByteRole::octet (0 = first written); 0 otherwise.
std::uint8_t octet_index(const ParameterInfo& parameter) noexcept;

// Whether `value` is in one of the parameter's spans, ignoring firmware.
bool value_in_spans(const ParameterInfo& parameter, std::uint8_t value) noexcept;

// Whether `model` has the parameter at all (firmware version, Ethernet).
Status check_parameter_available(std::uint8_t address, const SensorModel& model);
// Whether `model` accepts byte `value` at `address`. The error names the accepted values.
Status check_parameter_byte(std::uint8_t address, std::uint8_t value, const SensorModel& model);

// The default byte; MAC bytes 64/65 are taken from the serial number.
std::uint8_t default_byte(const ParameterInfo& parameter, std::uint32_t serial_number) noexcept;

// "01-05; 06-08 from LS5.6.0" — for errors, CLI help and docs.
std::string describe_accepted_values(const ParameterInfo& parameter);
// "05" style two-digit upper-case hex, for messages and tables.
std::string hex_byte(std::uint8_t value);

}  // namespace rangekit::ls5
