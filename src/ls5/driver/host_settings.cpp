#include "rangekit/ls5/host_settings.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <utility>

#include "rangekit/ls5/result_code.hpp"
#include "rangekit/ls5/settings.hpp"

namespace rangekit::ls5 {
namespace {

using F = SettingForm;
using L = LogicalValueId;

// One row per value. Single bytes carry their table 9.2 cli_name; multi-byte
// values get a unit suffix so that `period-ms=1` reads as what it means.
constexpr HostSetting settings[] = {
    {"network-address", "", F::byte_number, address::network_address, L::none, true, true},
    {"power-on-state", "", F::byte_named, address::power_on_state},
    {"analog-output", "", F::byte_named, address::analog_enabled},
    {"byte-format", "", F::byte_named, address::byte_format, L::none, true, true},
    {"baud-rate", "baud", F::byte_named, address::baud_rate, L::none, true, true},
    {"period-ms", "ms", F::value_number, 0, L::measurement_period},
    {"thinning", "", F::byte_number, address::thinning},
    {"signal-absence-ms", "ms", F::value_number, 0, L::signal_absence_time},
    {"pre-filter", "", F::byte_named, address::pre_filter},
    {"averaging-points", "", F::byte_number, address::averaging_points},
    {"median-points", "", F::byte_number, address::median_points},
    {"result-type", "", F::byte_named, address::result_type},
    {"analog-lower", "code", F::value_number, 0, L::analog_lower_limit},
    {"analog-lower-mm", "mm", F::value_mm, 0, L::analog_lower_limit, false},
    {"analog-upper", "code", F::value_number, 0, L::analog_upper_limit},
    {"analog-upper-mm", "mm", F::value_mm, 0, L::analog_upper_limit, false},
    {"discrete-outputs", "", F::byte_named, address::discrete_outputs},
    {"output1-first-swing", "code", F::value_number, 0, L::output1_first_swing},
    {"output1-first-swing-mm", "mm", F::value_mm, 0, L::output1_first_swing, false},
    {"output1-second-swing", "code", F::value_number, 0, L::output1_second_swing},
    {"output1-second-swing-mm", "mm", F::value_mm, 0, L::output1_second_swing, false},
    {"output2-first-swing", "code", F::value_number, 0, L::output2_first_swing},
    {"output2-first-swing-mm", "mm", F::value_mm, 0, L::output2_first_swing, false},
    {"output2-second-swing", "code", F::value_number, 0, L::output2_second_swing},
    {"output2-second-swing-mm", "mm", F::value_mm, 0, L::output2_second_swing, false},
    {"triggering", "", F::byte_named, address::triggering},
    {"latching", "", F::byte_named, address::latching},
    {"max-exposure-us", "µs", F::value_number, 0, L::max_exposure_time},
    {"priority", "", F::byte_named, address::priority},
    {"analog-fixed-range", "code", F::value_number, 0, L::analog_fixed_range},
    {"analog-fixed-range-mm", "mm", F::value_range_mm, 0, L::analog_fixed_range, false},
    {"discrete-fixed-range", "code", F::value_number, 0, L::discrete_fixed_range},
    {"discrete-fixed-range-mm", "mm", F::value_range_mm, 0, L::discrete_fixed_range, false},
    {"ip-address", "", F::value_address, 0, L::sensor_ip},
    {"gateway", "", F::value_address, 0, L::gateway_ip},
    {"subnet-mask", "", F::value_address, 0, L::subnet_mask},
    {"destination-ip", "", F::value_address, 0, L::destination_ip},
    {"mac-address", "", F::value_address, 0, L::sensor_mac},
    {"destination-mac", "", F::value_address, 0, L::destination_mac},
    {"destination-port", "", F::value_number, 0, L::destination_port},
    {"source-port", "", F::value_number, 0, L::source_port},
    {"udp-auto-stream", "", F::byte_named, address::udp_auto_stream},
};

bool is_value(const HostSetting& setting) noexcept { return setting.value != L::none; }

std::string trim_number(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  std::string text = buffer;
  if (text.find('.') != std::string::npos) {
    while (text.back() == '0') text.pop_back();
    if (text.back() == '.') text.pop_back();
  }
  return text;
}

Result<double> parse_number(const HostSetting& setting, std::string_view text) {
  std::string copy(text);
  char* end = nullptr;
  const double value = std::strtod(copy.c_str(), &end);
  if (copy.empty() || end != copy.c_str() + copy.size() || !std::isfinite(value)) {
    return make_error(Errc::bad_number, std::string(setting.name) + "='" + copy + "' is not a number");
  }
  return value;
}

Result<std::uint64_t> parse_whole(const HostSetting& setting, std::string_view text) {
  std::uint64_t value = 0;
  int base = 10;
  if (text.size() > 2 && (text.substr(0, 2) == "0x" || text.substr(0, 2) == "0X")) {
    text.remove_prefix(2);
    base = 16;
  }
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value, base);
  if (text.empty() || error != std::errc{} || end != text.data() + text.size()) {
    return make_error(Errc::bad_number,
                      std::string(setting.name) + "='" + std::string(text) + "' is not a whole number");
  }
  return value;
}

Error refused(const HostSetting& setting, std::string_view text, const SettingContext& context, const Error& why) {
  return make_error(why.code, std::string(setting.name) + "=" + std::string(text) + " refused: allowed " +
                                  describe_setting_values(setting, context) + " (" + why.message + ")");
}

// A parameter byte the table refuses is explained by the allowed values alone: the
// table's own text speaks in hex bytes ("does not accept 63"), which the user never
// typed (docs/cli.md: one base per message). Model and firmware refusals pass through.
Error byte_refused(const HostSetting& setting, std::string_view text, const SettingContext& context,
                   const ParameterWrite& write, const Error& why) {
  if (!value_in_spans(*find_parameter(write.address), write.value)) {
    return refused(setting, text, context, make_error(why.code, "not one of these"));
  }
  return refused(setting, text, context, why);
}

Result<double> range_of(const HostSetting& setting, const SettingContext& context) {
  if (!context.range_mm || *context.range_mm <= 0) {
    return make_error(Errc::unsupported,
                      std::string(setting.name) + " needs the sensor's range from identification (ID) to convert mm");
  }
  return *context.range_mm;
}

Result<std::uint64_t> raw_from_text(const HostSetting& setting, const LogicalValueInfo& info, std::string_view text,
                                    const SettingContext& context) {
  switch (setting.form) {
    case F::value_number: {
      auto number = parse_number(setting, text);
      if (!number) return number.error();
      const double raw = *number / info.scale;
      const double rounded = std::round(raw);
      if (std::fabs(raw - rounded) > 1e-6) {
        return make_error(Errc::out_of_range,
                          "not a whole number of " + trim_number(info.scale, 3) + " " + std::string(setting.unit));
      }
      if (rounded < 0 || rounded > static_cast<double>(info.max)) {
        return make_error(Errc::out_of_range, "outside the range");
      }
      return static_cast<std::uint64_t>(rounded);
    }
    case F::value_mm: {
      auto range = range_of(setting, context);
      if (!range) return range.error();
      auto mm = parse_number(setting, text);
      if (!mm) return mm.error();
      auto code = code_from_distance(*mm, *range);  // formula 8.5, L23
      if (!code) return code.error();
      return *code;
    }
    case F::value_range_mm: {
      auto range = range_of(setting, context);
      if (!range) return range.error();
      auto mm = parse_number(setting, text);
      if (!mm) return mm.error();
      const double code = std::round(*mm / *range * static_cast<double>(max_result_code));
      if (code < 0 || code > static_cast<double>(info.max)) return make_error(Errc::out_of_range, "outside the range");
      return static_cast<std::uint64_t>(code);
    }
    case F::value_address: {
      std::uint64_t value = 0;
      const bool mac = info.kind == ValueKind::mac;
      const std::size_t parts = mac ? 6 : 4;
      std::size_t index = 0;
      std::string_view rest = text;
      for (; index < parts; ++index) {
        const std::size_t cut = rest.find(mac ? ':' : '.');
        const std::string_view part = rest.substr(0, cut);
        unsigned byte = 0;
        const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), byte, mac ? 16 : 10);
        if (part.empty() || error != std::errc{} || end != part.data() + part.size() || byte > 255) break;
        value = (value << 8U) | byte;
        if (cut == std::string_view::npos) {
          ++index;
          rest = {};
          break;
        }
        rest.remove_prefix(cut + 1);
      }
      if (index != parts || !rest.empty()) {
        return make_error(Errc::bad_number,
                          mac ? "not a MAC address like 1E:30:6C:A2:00:9D" : "not an IPv4 address like 192.168.0.3");
      }
      return value;
    }
    default:
      return make_error(Errc::wrong_form, "not a multi-byte value");
  }
}

std::string describe_spans_decimal(const ParameterInfo& parameter) {
  std::string text;
  for (const ValueSpan& span : parameter.accepted) {
    if (!text.empty()) text += "; ";
    text += std::to_string(span.first);
    if (span.last != span.first) {
      text += span.step == 1 ? "-" : ", " + std::to_string(span.first + span.step) + ", ..., ";
      text += std::to_string(span.last);
    }
    if (span.step == 2) text += " (odd)";
    if (span.since != any_firmware) text += " from " + span.since.to_string();
  }
  return text;
}

}  // namespace

std::vector<std::uint8_t> HostSetting::addresses() const {
  if (value == L::none) return {parameter};
  const auto& info = logical_value_info(value);
  return {info.addresses.begin(), info.addresses.end()};
}

std::span<const HostSetting> host_setting_table() noexcept { return settings; }

const HostSetting* find_host_setting(std::string_view name) noexcept {
  for (const HostSetting& setting : settings) {
    if (setting.name == name) return &setting;
  }
  return nullptr;
}

const HostSetting* host_setting_for_parameter(std::uint8_t address) noexcept {
  for (const HostSetting& setting : settings) {
    if (!setting.canonical) continue;
    if (!is_value(setting)) {
      if (setting.parameter == address) return &setting;
      continue;
    }
    for (const std::uint8_t part : logical_value_info(setting.value).addresses) {
      if (part == address) return &setting;
    }
  }
  return nullptr;
}

Status check_setting_available(const HostSetting& setting, const SensorModel& model) {
  for (const std::uint8_t address : setting.addresses()) {
    Status available = check_parameter_available(address, model);
    if (!available) {
      return make_error(available.error().code, std::string(setting.name) + ": " + available.error().message);
    }
  }
  return ok_status();
}

bool setting_is_numeric(const HostSetting& setting) noexcept {
  return setting.form == F::byte_number || setting.form == F::value_number || setting.form == F::value_mm ||
         setting.form == F::value_range_mm;
}

std::string describe_setting_values(const HostSetting& setting, const SettingContext& context) {
  if (!is_value(setting)) {
    const ParameterInfo& parameter = *find_parameter(setting.parameter);
    if (setting.form == F::byte_number) return describe_spans_decimal(parameter);
    std::string text;
    for (const NamedValue& named : parameter.named_values) {
      if (!value_in_spans(parameter, named.value)) continue;
      if (!text.empty()) text += " | ";
      text += named.cli_name;
    }
    return text;
  }
  const LogicalValueInfo& info = logical_value_info(setting.value);
  const std::string unit = setting.unit.empty() || setting.unit == "code" ? "" : " " + std::string(setting.unit);
  switch (setting.form) {
    case F::value_number:
      return trim_number(static_cast<double>(info.min) * info.scale, 3) + "-" +
             trim_number(static_cast<double>(info.max) * info.scale, 3) + unit;
    case F::value_mm:
    case F::value_range_mm: {
      if (!context.range_mm) return "mm within the sensor's range (needs ID)";
      const double per_code = *context.range_mm / static_cast<double>(max_result_code);
      return trim_number(static_cast<double>(info.min) * per_code, 4) + "-" +
             trim_number(static_cast<double>(info.max) * per_code, 4) + " mm";
    }
    case F::value_address:
      return info.kind == ValueKind::mac ? "a MAC address XX:XX:XX:XX:XX:XX" : "an IPv4 address a.b.c.d";
    default:
      return "";
  }
}

Result<ParameterWrites> encode_setting(const HostSetting& setting, std::string_view text,
                                       const SettingContext& context) {
  Status available = check_setting_available(setting, context.model);
  if (!available) return available.error();
  if (!is_value(setting)) {
    const ParameterInfo& parameter = *find_parameter(setting.parameter);
    std::optional<std::uint8_t> byte;
    if (setting.form == F::byte_named) {
      for (const NamedValue& named : parameter.named_values) {
        if (named.cli_name == text) byte = named.value;
      }
      if (!byte) {
        return refused(setting, text, context, make_error(Errc::out_of_range, "not one of the names"));
      }
    } else {
      auto number = parse_whole(setting, text);
      if (!number) return refused(setting, text, context, number.error());
      if (*number > 0xFF) return refused(setting, text, context, make_error(Errc::out_of_range, "too large"));
      byte = static_cast<std::uint8_t>(*number);
    }
    Status accepted = check_parameter_byte(setting.parameter, *byte, context.model);
    if (!accepted) return byte_refused(setting, text, context, {setting.parameter, *byte}, accepted.error());
    ParameterWrites writes;
    writes.items[0] = {setting.parameter, *byte};
    writes.count = 1;
    return writes;
  }
  const LogicalValueInfo& info = logical_value_info(setting.value);
  auto raw = raw_from_text(setting, info, text, context);
  if (!raw) return refused(setting, text, context, raw.error());
  auto writes = split_value(info, *raw);  // table order; Driver::set sends them in write order (L50, L62)
  if (!writes) return refused(setting, text, context, writes.error());
  for (const ParameterWrite& write : writes->view()) {
    Status accepted = check_parameter_byte(write.address, write.value, context.model);
    if (!accepted) return byte_refused(setting, text, context, write, accepted.error());
  }
  return writes;
}

Status check_setting_offline(const HostSetting& setting, std::string_view text) {
  SettingContext most_permissive;
  most_permissive.model.firmware = FirmwareVersion{0xFFFF, 0xFFFF};
  most_permissive.model.ethernet = true;
  auto writes = encode_setting(setting, text, most_permissive);
  if (!writes && writes.error().code != Errc::unsupported) return writes.error();  // unsupported: needs the sensor
  return ok_status();
}

Result<std::string> format_setting(const HostSetting& setting, std::span<const std::uint8_t> bytes,
                                   const SettingContext& context) {
  if (!is_value(setting)) {
    if (bytes.size() != 1) return make_error(Errc::wrong_form, std::string(setting.name) + " is one byte");
    const ParameterInfo& parameter = *find_parameter(setting.parameter);
    if (setting.form == F::byte_named) {
      for (const NamedValue& named : parameter.named_values) {
        if (named.value == bytes[0]) return std::string(named.cli_name);
      }
      return make_error(Errc::out_of_range, std::string(setting.name) + ": the sensor reported " + hex_byte(bytes[0]) +
                                                ", not in table 9.2");
    }
    return std::to_string(bytes[0]);
  }
  const LogicalValueInfo& info = logical_value_info(setting.value);
  auto raw = combine_bytes(info, bytes);
  if (!raw) return raw.error();
  switch (setting.form) {
    case F::value_number:
      return trim_number(static_cast<double>(*raw) * info.scale, 1);
    case F::value_mm:
    case F::value_range_mm: {
      auto range = range_of(setting, context);
      if (!range) return range.error();
      return trim_number(static_cast<double>(*raw) * *range / static_cast<double>(max_result_code), 4);
    }
    case F::value_address:
      return info.kind == ValueKind::mac ? format_mac(*raw) : format_ipv4(static_cast<std::uint32_t>(*raw));
    default:
      return make_error(Errc::wrong_form, "not a multi-byte value");
  }
}

}  // namespace rangekit::ls5
