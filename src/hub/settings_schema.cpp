// GET /api/sensors/{name}/settings/schema: built here from the ULS registry and the LS5
// host catalog, so the faces serve it without reaching into a sensor family's code.
#include "rangekit/hub/settings_schema.hpp"

#include "rangekit/ls5/host_settings.hpp"
#include "rangekit/ls5/logical_values.hpp"
#include "rangekit/ls5/parameters.hpp"

#include "rangekit/uls/commands.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/formulas.hpp"
#include "rangekit/uls/named_settings.hpp"

namespace rangekit::hub {

namespace {

// The unit of a setting's readable value, as its name carries it (named_settings.hpp).
std::string readable_unit(const uls::CommandInfo& command) {
  using uls::ValueKind;
  if (command.is_distance()) return "m";
  switch (command.kind) {
    case ValueKind::milliamps:
      return "mA";
    case ValueKind::seconds:
    case ValueKind::hex_pulses:
      return "s";
    case ValueKind::prf_list:
      return "Hz";
    default:
      return std::string(command.unit);
  }
}

nlohmann::json schema_row(const uls::CommandInfo& command, std::string key) {
  nlohmann::json row{{"key", std::move(key)},
                     {"mnemonic", command.mnemonic},
                     {"title", command.title},
                     {"kind", uls::value_kind_name(command.kind)},
                     {"unit", readable_unit(command)},
                     {"writable", command.has_set()},
                     {"min_fields", command.set_fields_min},
                     {"max_fields", command.set_fields_max},
                     {"error", command.value_error},
                     {"reference", command.reference}};
  if (command.has_set()) {
    if (command.kind == uls::ValueKind::hex_pulses) {
      // Read and written in seconds (U21): the pulse count's range over 3000 pulses a second.
      row["min"] = uls::trip_timeout_seconds(static_cast<std::uint64_t>(command.min));
      row["max"] = uls::trip_timeout_seconds(static_cast<std::uint64_t>(command.max));
    } else {
      row["min"] = command.min;
      row["max"] = command.max;
    }
  }
  nlohmann::json values = nlohmann::json::array();
  for (const uls::ValueName& entry : command.value_names)
    values.push_back({{"value", entry.value}, {"name", entry.name}});
  if (values.empty() && command.kind == uls::ValueKind::flag) {
    values.push_back({{"value", 0}, {"name", "off"}});
    values.push_back({{"value", 1}, {"name", "on"}});
  }
  if (command.id == uls::CommandId::bin_size) {
    // The Interface Program's own labels, "2.5 (13)": accuracy in cm, range in m (§2, U33).
    for (const uls::BinSizeInfo& size : uls::bin_size_table()) {
      for (auto& value : values)
        if (value["value"] == static_cast<int>(size.size)) value["label"] = size.interface_label;
    }
  }
  if (!values.empty()) row["values"] = values;
  return row;
}

}  // namespace

nlohmann::json uls_settings_schema() {
  nlohmann::json settings = nlohmann::json::array();
  for (const uls::CommandInfo& command : uls::command_table()) {
    if (command.access == uls::Access::action || command.id == uls::CommandId::measure) continue;
    if (command.kind == uls::ValueKind::baud_with_port) {
      settings.push_back(schema_row(command, "baud-configuration"));
      settings.push_back(schema_row(command, "baud-output"));
    } else {
      settings.push_back(schema_row(command, uls::named::setting_key(command)));
    }
  }
  // §10's table, so a page can show a refusal as the Interface Program does ("ULS Interface Display").
  nlohmann::json errors = nlohmann::json::array();
  for (const uls::ErrorInfo& error : uls::error_table())
    errors.push_back({{"number", error.number}, {"explanation", error.explanation}, {"display", error.display}});
  return nlohmann::json{{"family", "uls"}, {"settings", settings}, {"errors", errors}};
}

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

nlohmann::json ls5_settings_schema() {
  nlohmann::json settings = nlohmann::json::array();
  for (const ls5::HostSetting& setting : ls5::host_setting_table()) {
    // The -mm forms are views of the code values through the ID's range (L48): the page converts.
    if (setting.canonical) settings.push_back(ls5_schema_row(setting));
  }
  return nlohmann::json{{"family", "ls5"}, {"settings", settings}};
}

}  // namespace rangekit::hub
