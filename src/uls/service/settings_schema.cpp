// GET /api/sensors/{name}/settings/schema of a ULS: every setting of §8's command table (the
// CLI's registry) under the name `get` prints, its range in the unit of that name, the §10
// number a unit answers outside it and the named values; plus §10's table of errors.
#include "uls/service/service.hpp"

#include "rangekit/uls/commands.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/formulas.hpp"
#include "rangekit/uls/named_settings.hpp"

namespace rangekit::uls::service {

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

nlohmann::json settings_schema() {
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

}  // namespace rangekit::uls::service
