// GET /api/sensors/{name}/settings/schema of an LS5: every setting of table 9.2 under the name
// `rangekit ls5 get` prints (one row per value, not per byte), its parameter addresses, range,
// step, named values and the firmware each needs, and whether it changes how the service
// reaches the sensor (address, baud rate, byte format: not written by the API).
#include "ls5/service/service.hpp"

#include <algorithm>

#include "rangekit/ls5/host_settings.hpp"
#include "rangekit/ls5/logical_values.hpp"
#include "rangekit/ls5/parameters.hpp"

namespace rangekit::ls5::service {

namespace {

nlohmann::json since_of(const ls5::FirmwareVersion& version) {
  if (version == ls5::any_firmware) return nullptr;
  return version.to_string();
}

// The firmware a byte value needs: that of the span holding it (table 9.2 notes 2-4, L6).
ls5::FirmwareVersion value_since(const ls5::ParameterInfo& parameter, std::uint8_t value) {
  for (const ls5::ValueSpan& span : parameter.accepted) {
    if (value >= span.first && value <= span.last && (value - span.first) % span.step == 0) return span.since;
  }
  return ls5::any_firmware;
}

nlohmann::json ls5_schema_row(const ls5::HostSetting& setting) {
  using ls5::SettingForm;
  nlohmann::json addresses = nlohmann::json::array();
  ls5::FirmwareVersion since = ls5::any_firmware;
  bool ethernet_only = false;
  for (const std::uint8_t address : setting.addresses()) {
    addresses.push_back(ls5::hex_byte(address));
    const ls5::ParameterInfo& parameter = *ls5::find_parameter(address);
    since = std::max(since, parameter.since);
    ethernet_only = ethernet_only || parameter.ethernet_only;
  }
  nlohmann::json row{{"key", setting.name},       {"unit", setting.unit}, {"addresses", addresses},
                     {"writable", !setting.link}, {"link", setting.link}, {"ethernet_only", ethernet_only},
                     {"since", since_of(since)}};
  if (setting.value == ls5::LogicalValueId::none) {
    const ls5::ParameterInfo& parameter = *ls5::find_parameter(setting.parameter);
    row["title"] = parameter.name;
    if (setting.form == SettingForm::byte_named) {
      nlohmann::json values = nlohmann::json::array();
      for (const ls5::NamedValue& named : parameter.named_values) {
        if (!ls5::value_in_spans(parameter, named.value)) continue;
        values.push_back({{"value", named.cli_name},
                          {"name", named.cli_name},
                          {"label", named.meaning},
                          {"byte", ls5::hex_byte(named.value)},
                          {"since", since_of(value_since(parameter, named.value))}});
      }
      row["values"] = values;
    } else {
      // byte_number: the table's spans, e.g. thinning 01-FF, median points 01, 03, ..., 31.
      row["min"] = parameter.accepted.front().first;
      row["max"] = parameter.accepted.back().last;
      row["step"] = parameter.accepted.front().step;
    }
    return row;
  }
  const ls5::LogicalValueInfo& info = ls5::logical_value_info(setting.value);
  row["title"] = info.name;
  if (setting.form == SettingForm::value_number) {
    row["min"] = static_cast<double>(info.min) * info.scale;
    row["max"] = static_cast<double>(info.max) * info.scale;
    row["step"] = info.scale;
  } else if (setting.form == SettingForm::value_address) {
    row["format"] = info.kind == ls5::ValueKind::mac ? "mac" : "ipv4";
  }
  return row;
}

}  // namespace

nlohmann::json settings_schema() {
  nlohmann::json settings = nlohmann::json::array();
  for (const ls5::HostSetting& setting : ls5::host_setting_table()) {
    // The -mm forms are views of the code values through the ID's range (L48): the page converts.
    if (setting.canonical) settings.push_back(ls5_schema_row(setting));
  }
  return nlohmann::json{{"family", "ls5"}, {"settings", settings}};
}

}  // namespace rangekit::ls5::service
