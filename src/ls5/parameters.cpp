#include "rangekit/ls5/parameters.hpp"

#include <array>

#include "ls5/messages.hpp"

namespace rangekit::ls5 {
namespace {

using L = LogicalValueId;
using D = DefaultSource;

// ---- Accepted values, as table 9.2 prints them ----
constexpr ValueSpan any_byte[] = {{0x00, 0xFF}};
constexpr ValueSpan nonzero_byte[] = {{0x01, 0xFF}};
constexpr ValueSpan zero_or_one[] = {{0x00, 0x01}};
constexpr ValueSpan byte_format_codes[] = {{0x00, 0x05}};
constexpr ValueSpan baud_codes[] = {{0x01, 0x05}, {0x06, 0x08, 1, firmware_6_0}};  // note 2
constexpr ValueSpan median_points[] = {{0x01, 0x31, 2}};                           // L4: odd, hex
constexpr ValueSpan high_byte_of_code[] = {{0x00, 0xC3}};                          // codes 0-50000
constexpr ValueSpan discrete_outputs[] = {{0x00, 0x02}, {0x10, 0x12}, {0x20, 0x22}};
constexpr ValueSpan latching_modes[] = {{0x00, 0x01}, {0x02, 0x09, 1, firmware_9_0}};  // §8.14

// ---- Names of enumerated values ----
constexpr NamedValue power_on_names[] = {{0x00, "off", "off"}, {0x01, "on", "on"}};
constexpr NamedValue enabled_names[] = {{0x00, "disabled", "disabled"}, {0x01, "enabled", "enabled"}};
constexpr NamedValue byte_format_names[] = {
    {0x00, "8N1", "no parity, 1 stop bit"},        {0x01, "8E1", "parity control, 1 stop bit"},
    {0x02, "8O1", "imparity control, 1 stop bit"}, {0x03, "8N2", "no parity, 2 stop bits"},
    {0x04, "8E2", "parity control, 2 stop bits"},  {0x05, "8O2", "imparity control, 2 stop bits"},
};
constexpr NamedValue baud_names[] = {
    {0x01, "9600", "9600 baud"},     {0x02, "19200", "19200 baud"},   {0x03, "38400", "38400 baud"},
    {0x04, "57600", "57600 baud"},   {0x05, "115200", "115200 baud"}, {0x06, "230400", "230400 baud"},
    {0x07, "460800", "460800 baud"}, {0x08, "921600", "921600 baud"},
};
constexpr NamedValue pre_filter_names[] = {{0x00, "average", "averaging over n values"},
                                           {0x01, "median", "median filtering"}};
constexpr NamedValue result_type_names[] = {
    {0x00, "pure", "in its pure form"},
    {0x01, "derivative", "the derivative of the signal (the difference between the current and previous results)"},
};
// "low"/"high": enabled with initial value 0/1 (§8.11).
constexpr NamedValue discrete_output_names[] = {
    {0x00, "off-off", "output 1 disabled; output 2 disabled"},
    {0x01, "off-low", "output 1 disabled; output 2 enabled, initial value 0"},
    {0x02, "off-high", "output 1 disabled; output 2 enabled, initial value 1"},
    {0x10, "low-off", "output 1 enabled, initial value 0; output 2 disabled"},
    {0x11, "low-low", "output 1 enabled, initial value 0; output 2 enabled, initial value 0"},
    {0x12, "low-high", "output 1 enabled, initial value 0; output 2 enabled, initial value 1"},
    {0x20, "high-off", "output 1 enabled, initial value 1; output 2 disabled"},
    {0x21, "high-low", "output 1 enabled, initial value 1; output 2 enabled, initial value 0"},
    {0x22, "high-high", "output 1 enabled, initial value 1; output 2 enabled, initial value 1"},
};
constexpr NamedValue triggering_names[] = {{0x00, "timer", "by timer"},
                                           {0x01, "sync-input", "by an external synchronization input"}};
constexpr NamedValue latching_names[] = {
    {0x00, "off", "disabled"},
    {0x01, "latch", "enabled, only with a record in the latch"},
    {0x02, "analog", "latch, and the limits of the analog output are recalculated"},
    {0x03, "analog-rom", "as 02, and the analog output limits are also recorded to the ROM"},
    {0x04, "output1", "latch, and the limits of the 1st discrete output are recalculated"},
    {0x05, "output1-rom", "as 04, and the limits of the 1st discrete output are also recorded to the ROM"},
    {0x06, "output2", "latch, and the limits of the 2nd discrete output are recalculated"},
    {0x07, "output2-rom", "as 06, and the limits of the 2nd discrete output are also recorded to the ROM"},
    {0x08, "output1-lower-output2-upper",
     "latch, and the lower limit of the 1st and upper limit of the 2nd discrete outputs are recalculated"},
    {0x09, "output1-lower-output2-upper-rom", "as 08, and those limits are also recorded to the ROM"},
};
constexpr NamedValue priority_names[] = {{0x00, "frequency", "priority of the measurement frequency"},
                                         {0x01, "sensitivity", "sensitivity priority"}};
constexpr NamedValue on_off_names[] = {{0x00, "off", "off"}, {0x01, "on", "on"}};

constexpr FirmwareVersion any = any_firmware;
constexpr FirmwareVersion v7 = firmware_7_0;
constexpr FirmwareVersion v8 = firmware_8_0;
constexpr FirmwareVersion v9 = firmware_9_0;
constexpr FirmwareVersion v12 = firmware_12_x;

// Table 9.2, one row per address. Two-byte values: significance 0 is the low byte.
// IP and MAC octets: byte 0 (the first one written) is the most significant.
constexpr ParameterInfo parameters[] = {
    {0x01, "Network address", "network-address", nonzero_byte, 0x01},
    {0x02, "Sensor on/off when power is supplied", "power-on-state", zero_or_one, 0x01, D::fixed, L::none, 0, any,
     false, power_on_names},
    {0x03, "Analog output is enabled/disabled", "analog-output", zero_or_one, 0x01, D::fixed, L::none, 0, any, false,
     enabled_names},
    {0x04, "Byte format at work with serial protocols", "byte-format", byte_format_codes, 0x00, D::fixed, L::none, 0,
     any, false, byte_format_names},
    {0x05, "Baud rate", "baud-rate", baud_codes, 0x05, D::fixed, L::none, 0, any, false, baud_names},
    {0x06, "Measurement period, low byte", "period.low", any_byte, 0x64, D::fixed, L::measurement_period, 0},
    {0x07, "Measurement period, high byte", "period.high", any_byte, 0x00, D::fixed, L::measurement_period, 1},
    {0x08, "Coefficient of the data stream thinning", "thinning", nonzero_byte, 0x01},
    {0x09, "Acceptable time of signal absence, low byte", "signal-absence-time.low", any_byte, 0x0A, D::fixed,
     L::signal_absence_time, 0},
    {0x0A, "Acceptable time of signal absence, high byte", "signal-absence-time.high", any_byte, 0x00, D::fixed,
     L::signal_absence_time, 1},
    {0x0B, "Data pre-filtering type", "pre-filter", zero_or_one, 0x00, D::fixed, L::none, 0, any, false,
     pre_filter_names},
    {0x0C, "Number of averaging points", "averaging-points", nonzero_byte, 0x01},
    {0x0D, "Number of points of the median filter", "median-points", median_points, 0x05},
    {0x0E, "Type of preliminary result", "result-type", zero_or_one, 0x00, D::fixed, L::none, 0, v8, false,
     result_type_names},
    {0x11, "Lower limit of the analog output, low byte", "analog-lower.low", any_byte, 0x00, D::fixed,
     L::analog_lower_limit, 0},
    {0x12, "Lower limit of the analog output, high byte", "analog-lower.high", high_byte_of_code, 0x00, D::fixed,
     L::analog_lower_limit, 1},
    {0x13, "Upper limit of the analog output, low byte", "analog-upper.low", any_byte, 0x50, D::fixed,
     L::analog_upper_limit, 0},
    {0x14, "Upper limit of the analog output, high byte", "analog-upper.high", high_byte_of_code, 0xC3, D::fixed,
     L::analog_upper_limit, 1},
    {0x15, "Discrete outputs setting", "discrete-outputs", discrete_outputs, 0x12, D::fixed, L::none, 0, any, false,
     discrete_output_names},
    {0x16, "First swing of the first discrete output, low byte", "output1-first-swing.low", any_byte, 0x00, D::fixed,
     L::output1_first_swing, 0},
    {0x17, "First swing of the first discrete output, high byte", "output1-first-swing.high", high_byte_of_code, 0x00,
     D::fixed, L::output1_first_swing, 1},
    {0x18, "Second swing of the first discrete output, low byte", "output1-second-swing.low", any_byte, 0x50, D::fixed,
     L::output1_second_swing, 0},
    {0x19, "Second swing of the first discrete output, high byte", "output1-second-swing.high", high_byte_of_code, 0xC3,
     D::fixed, L::output1_second_swing, 1},
    {0x1A, "First swing of the second discrete output, low byte", "output2-first-swing.low", any_byte, 0x00, D::fixed,
     L::output2_first_swing, 0},
    {0x1B, "First swing of the second discrete output, high byte", "output2-first-swing.high", high_byte_of_code, 0x00,
     D::fixed, L::output2_first_swing, 1},
    {0x1C, "Second swing of the second discrete output, low byte", "output2-second-swing.low", any_byte, 0x50, D::fixed,
     L::output2_second_swing, 0},
    {0x1D, "Second swing of the second discrete output, high byte", "output2-second-swing.high", high_byte_of_code,
     0xC3, D::fixed, L::output2_second_swing, 1},
    {0x1E, "Triggering", "triggering", zero_or_one, 0x00, D::fixed, L::none, 0, any, false, triggering_names},
    {0x1F, "Latching", "latching", latching_modes, 0x01, D::fixed, L::none, 0, any, false, latching_names},
    {0x20, "Maximum exposure time, low byte", "max-exposure.low", any_byte, 0xB8, D::fixed, L::max_exposure_time, 0,
     v7},
    {0x21, "Maximum exposure time, high byte", "max-exposure.high", any_byte, 0x24, D::fixed, L::max_exposure_time, 1,
     v7},
    {0x22, "Priority of measurement of frequency/sensitivity", "priority", zero_or_one, 0x01, D::fixed, L::none, 0, v7,
     false, priority_names},
    {0x23, "Fixed range of the analog output, low byte", "analog-fixed-range.low", any_byte, 0x10, D::fixed,
     L::analog_fixed_range, 0, v9},
    {0x24, "Fixed range of the analog output, high byte", "analog-fixed-range.high", any_byte, 0x27, D::fixed,
     L::analog_fixed_range, 1, v9},
    {0x25, "Fixed range of the discrete outputs, low byte", "discrete-fixed-range.low", any_byte, 0x10, D::fixed,
     L::discrete_fixed_range, 0, v9},
    {0x26, "Fixed range of the discrete outputs, high byte", "discrete-fixed-range.high", any_byte, 0x27, D::fixed,
     L::discrete_fixed_range, 1, v9},
    {0x50, "Sensor IP address, byte 0", "ip-address.0", any_byte, 0xC0, D::fixed, L::sensor_ip, 3, v12, true},
    {0x51, "Sensor IP address, byte 1", "ip-address.1", any_byte, 0xA8, D::fixed, L::sensor_ip, 2, v12, true},
    {0x52, "Sensor IP address, byte 2", "ip-address.2", any_byte, 0x00, D::fixed, L::sensor_ip, 1, v12, true},
    {0x53, "Sensor IP address, byte 3", "ip-address.3", any_byte, 0x03, D::fixed, L::sensor_ip, 0, v12, true},
    {0x54, "Gateway IP address, byte 0", "gateway.0", any_byte, 0xC0, D::fixed, L::gateway_ip, 3, v12, true},
    {0x55, "Gateway IP address, byte 1", "gateway.1", any_byte, 0xA8, D::fixed, L::gateway_ip, 2, v12, true},
    {0x56, "Gateway IP address, byte 2", "gateway.2", any_byte, 0x00, D::fixed, L::gateway_ip, 1, v12, true},
    {0x57, "Gateway IP address, byte 3", "gateway.3", any_byte, 0x01, D::fixed, L::gateway_ip, 0, v12, true},
    {0x58, "Subnetwork mask, byte 0", "subnet-mask.0", any_byte, 0xFF, D::fixed, L::subnet_mask, 3, v12, true},
    {0x59, "Subnetwork mask, byte 1", "subnet-mask.1", any_byte, 0xFF, D::fixed, L::subnet_mask, 2, v12, true},
    {0x5A, "Subnetwork mask, byte 2", "subnet-mask.2", any_byte, 0xFF, D::fixed, L::subnet_mask, 1, v12, true},
    {0x5B, "Subnetwork mask, byte 3", "subnet-mask.3", any_byte, 0xFF, D::fixed, L::subnet_mask, 0, v12, true},
    {0x5C, "Destination IP address, byte 0", "destination-ip.0", any_byte, 0xFF, D::fixed, L::destination_ip, 3, v12,
     true},
    {0x5D, "Destination IP address, byte 1", "destination-ip.1", any_byte, 0xFF, D::fixed, L::destination_ip, 2, v12,
     true},
    {0x5E, "Destination IP address, byte 2", "destination-ip.2", any_byte, 0xFF, D::fixed, L::destination_ip, 1, v12,
     true},
    {0x5F, "Destination IP address, byte 3", "destination-ip.3", any_byte, 0xFF, D::fixed, L::destination_ip, 0, v12,
     true},
    {0x60, "MAC address of the sensor, byte 0", "mac-address.0", any_byte, 0x1E, D::fixed, L::sensor_mac, 5, v12, true},
    {0x61, "MAC address of the sensor, byte 1", "mac-address.1", any_byte, 0x30, D::fixed, L::sensor_mac, 4, v12, true},
    {0x62, "MAC address of the sensor, byte 2", "mac-address.2", any_byte, 0x6C, D::fixed, L::sensor_mac, 3, v12, true},
    {0x63, "MAC address of the sensor, byte 3", "mac-address.3", any_byte, 0xA2, D::fixed, L::sensor_mac, 2, v12, true},
    {0x64, "MAC address of the sensor, byte 4", "mac-address.4", any_byte, 0x00, D::serial_high_byte, L::sensor_mac, 1,
     v12, true},
    {0x65, "MAC address of the sensor, byte 5", "mac-address.5", any_byte, 0x00, D::serial_low_byte, L::sensor_mac, 0,
     v12, true},
    {0x66, "Destination MAC address, byte 0", "destination-mac.0", any_byte, 0xFF, D::fixed, L::destination_mac, 5, v12,
     true},
    {0x67, "Destination MAC address, byte 1", "destination-mac.1", any_byte, 0xFF, D::fixed, L::destination_mac, 4, v12,
     true},
    {0x68, "Destination MAC address, byte 2", "destination-mac.2", any_byte, 0xFF, D::fixed, L::destination_mac, 3, v12,
     true},
    {0x69, "Destination MAC address, byte 3", "destination-mac.3", any_byte, 0xFF, D::fixed, L::destination_mac, 2, v12,
     true},
    {0x6A, "Destination MAC address, byte 4", "destination-mac.4", any_byte, 0xFF, D::fixed, L::destination_mac, 1, v12,
     true},
    {0x6B, "Destination MAC address, byte 5", "destination-mac.5", any_byte, 0xFF, D::fixed, L::destination_mac, 0, v12,
     true},
    // Ports: the table lists the high byte first (L5). The low byte's printed "01-FF" would forbid
    // ports 256, 512, 1024, ... that "For the parameter itself: 0001-FFFF" allows: the low byte takes
    // 00-FF and the port is checked as a whole (L18, L51).
    {0x6C, "Destination port number, high byte", "destination-port.high", any_byte, 0x02, D::fixed, L::destination_port,
     1, v12, true},
    {0x6D, "Destination port number, low byte", "destination-port.low", any_byte, 0x5B, D::fixed, L::destination_port,
     0, v12, true},
    {0x6E, "Source port number, high byte", "source-port.high", any_byte, 0x13, D::fixed, L::source_port, 1, v12, true},
    {0x6F, "Source port number, low byte", "source-port.low", any_byte, 0x88, D::fixed, L::source_port, 0, v12, true},
    {0x70, "UDP data auto-stream", "udp-auto-stream", zero_or_one, 0x01, D::fixed, L::none, 0, v12, true, on_off_names},
};

constexpr bool sorted_by_address() {
  for (std::size_t i = 1; i < std::size(parameters); ++i) {
    if (parameters[i - 1].address >= parameters[i].address) return false;
  }
  return true;
}
static_assert(sorted_by_address(), "table 9.2 rows must be in ascending address order");

std::string describe(const ParameterInfo& parameter) {
  return hex_byte(parameter.address) + " (" + std::string(parameter.name) + ")";
}

Error needs_firmware(const std::string& what, const FirmwareVersion& since, const SensorModel& model) {
  return make_error(Errc::unsupported, "LS5 parameter " + what + " needs firmware " + since.to_string() +
                                           " or later; the sensor reports " + model.firmware.to_string());
}

}  // namespace

std::span<const ParameterInfo> parameter_table() noexcept { return parameters; }

const ParameterInfo* find_parameter(std::uint8_t address) noexcept {
  for (const ParameterInfo& parameter : parameters) {
    if (parameter.address == address) return &parameter;
  }
  return nullptr;
}

const ParameterInfo* find_parameter_by_cli_name(std::string_view cli_name) noexcept {
  for (const ParameterInfo& parameter : parameters) {
    if (parameter.cli_name == cli_name) return &parameter;
  }
  return nullptr;
}

ByteRole byte_role(const ParameterInfo& parameter) noexcept {
  switch (parameter.part_of) {
    case LogicalValueId::none:
      return ByteRole::whole;
    case LogicalValueId::sensor_ip:
    case LogicalValueId::gateway_ip:
    case LogicalValueId::subnet_mask:
    case LogicalValueId::destination_ip:
    case LogicalValueId::sensor_mac:
    case LogicalValueId::destination_mac:
      return ByteRole::octet;
    default:
      return parameter.significance == 0 ? ByteRole::low_byte : ByteRole::high_byte;
  }
}

std::uint8_t octet_index(const ParameterInfo& parameter) noexcept {
  switch (parameter.part_of) {
    case LogicalValueId::sensor_ip:
    case LogicalValueId::gateway_ip:
    case LogicalValueId::subnet_mask:
    case LogicalValueId::destination_ip:
      return static_cast<std::uint8_t>(3 - parameter.significance);
    case LogicalValueId::sensor_mac:
    case LogicalValueId::destination_mac:
      return static_cast<std::uint8_t>(5 - parameter.significance);
    default:
      return 0;
  }
}

namespace {
const ValueSpan* span_holding(const ParameterInfo& parameter, std::uint8_t value) noexcept {
  for (const ValueSpan& span : parameter.accepted) {
    if (value >= span.first && value <= span.last && (value - span.first) % span.step == 0) return &span;
  }
  return nullptr;
}
}  // namespace

bool value_in_spans(const ParameterInfo& parameter, std::uint8_t value) noexcept {
  return span_holding(parameter, value) != nullptr;
}

Status check_parameter_available(std::uint8_t address, const SensorModel& model) {
  const ParameterInfo* parameter = find_parameter(address);
  if (parameter == nullptr) {
    return make_error(Errc::unknown_parameter, "LS5 parameter " + hex_byte(address) + " is not in table 9.2");
  }
  if (parameter->ethernet_only && !model.ethernet) {
    return make_error(Errc::unsupported,
                      "LS5 parameter " + describe(*parameter) + " exists on Ethernet sensors only (table 9.2 note 5)");
  }
  if (!model.firmware.at_least(parameter->since)) return needs_firmware(describe(*parameter), parameter->since, model);
  return ok_status();
}

Status check_parameter_byte(std::uint8_t address, std::uint8_t value, const SensorModel& model) {
  Status available = check_parameter_available(address, model);
  if (!available) return available;
  const ParameterInfo& parameter = *find_parameter(address);
  const ValueSpan* span = span_holding(parameter, value);
  if (span == nullptr) {
    return make_error(Errc::out_of_range, "LS5 parameter " + describe(parameter) + " does not accept " +
                                              hex_byte(value) + "; accepted: " + describe_accepted_values(parameter));
  }
  if (!model.firmware.at_least(span->since)) {
    return needs_firmware(describe(parameter) + " value " + hex_byte(value), span->since, model);
  }
  return ok_status();
}

std::uint8_t default_byte(const ParameterInfo& parameter, std::uint32_t serial_number) noexcept {
  switch (parameter.default_source) {
    case DefaultSource::fixed:
      return parameter.default_value;
    case DefaultSource::serial_high_byte:
      return static_cast<std::uint8_t>((serial_number >> 8U) & 0xFFU);
    case DefaultSource::serial_low_byte:
      return static_cast<std::uint8_t>(serial_number & 0xFFU);
  }
  return parameter.default_value;
}

std::string describe_accepted_values(const ParameterInfo& parameter) {
  std::string text;
  for (const ValueSpan& span : parameter.accepted) {
    if (!text.empty()) text += "; ";
    if (span.first == span.last) {
      text += hex_byte(span.first);
    } else if (span.step == 1) {
      text += hex_byte(span.first) + "-" + hex_byte(span.last);
    } else {
      text += hex_byte(span.first) + ", " + hex_byte(static_cast<std::uint8_t>(span.first + span.step)) + ", ..., " +
              hex_byte(span.last) + " (every " + std::to_string(span.step) + ")";
    }
    if (span.since != any_firmware) text += " from " + span.since.to_string();
  }
  return text;
}

std::string hex_byte(std::uint8_t value) { return text::hex_byte(value); }

}  // namespace rangekit::ls5
