#include "web/json_views.hpp"

#include <charconv>
#include <variant>

#include "rangekit/core/text.hpp"
#include "rangekit/record/format.hpp"
#include "rangekit/uls/commands.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/formulas.hpp"
#include "rangekit/uls/named_settings.hpp"

namespace rangekit::web {
namespace {

// "12.5" and "2000" as JSON numbers, everything else as the text it is.
nlohmann::json value_json(const std::string& text) {
  if (const auto number = text::parse_decimal(text)) {
    if (text.find('.') == std::string::npos && text.size() < 16) return static_cast<std::int64_t>(*number);
    return *number;
  }
  return text;
}

nlohmann::json fields_json(const std::vector<hub::Field>& fields) {
  nlohmann::json object = nlohmann::json::object();
  for (const hub::Field& field : fields) object[field.key] = value_json(field.value);
  return object;
}

std::string shortest(double value) {
  std::array<char, 64> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return {buffer.data(), result.ptr};
}

}  // namespace

nlohmann::json sensor_json(const hub::SensorSnapshot& sensor) {
  const hub::SensorConfig& config = sensor.config;
  const hub::SensorHealth& health = sensor.health;
  nlohmann::json out{{"name", config.name},
                     {"family", hub::family_name(config.family)},
                     {"port", config.port},
                     {"connected", health.connected},
                     {"streaming", sensor.streaming},
                     {"identity", fields_json(sensor.identity)},
                     {"status", fields_json(sensor.status)},
                     {"settings", fields_json(sensor.settings)},
                     {"last_id", sensor.last_sequence}};
  nlohmann::json units = nlohmann::json::object();
  for (const hub::Field& field : sensor.settings) {
    if (!field.unit.empty()) units[field.key] = field.unit;
  }
  out["setting_units"] = units;
  if (config.address) out["address"] = *config.address;
  if (!config.udp.empty()) out["udp"] = config.udp;
  nlohmann::json errors = nlohmann::json::object();
  for (const auto& [number, count] : health.errors_by_number) errors[std::to_string(number)] = count;
  nlohmann::json health_json{{"connected", health.connected},
                             {"rate_hz", health.rate_hz},
                             {"records", health.records},
                             {"errors", health.errors},
                             {"errors_by_number", errors},
                             {"no_signal", health.no_signal},
                             {"lost", health.lost},
                             {"bad_frames", health.bad_frames},
                             {"disconnects", health.disconnects},
                             {"reconnects", health.reconnects},
                             {"last_event", health.last_event}};
  if (health.last_seen) {
    std::string time;
    record::append_iso_time(time, *health.last_seen);
    health_json["last_seen"] = time;
  } else {
    health_json["last_seen"] = nullptr;
  }
  out["health"] = health_json;
  return out;
}

nlohmann::json capture_json(const hub::CaptureInfo& capture) {
  std::string started;
  record::append_iso_time(started, capture.started);
  nlohmann::json out{{"id", capture.id},     {"sensors", capture.sensors}, {"active", capture.active},
                     {"started", started},   {"samples", capture.samples}, {"events", capture.events},
                     {"lost", capture.lost}, {"error", capture.error},     {"stopped", nullptr}};
  if (capture.stopped) {
    std::string stopped;
    record::append_iso_time(stopped, *capture.stopped);
    out["stopped"] = stopped;
  }
  nlohmann::json links = nlohmann::json::object();
  for (const char* format : {"sqlite", "csv", "jsonl", "log"}) {
    links[format] = "/api/captures/" + capture.id + "/download?format=" + format;
  }
  out["download"] = links;
  return out;
}

const char* item_type(const hub::HubItem& item) {
  return std::holds_alternative<Sample>(item.item) ? "sample" : "event";
}

std::string item_json(const hub::HubItem& item) {
  std::string data;
  std::visit([&](const auto& value) { record::append_jsonl(data, value); }, item.item);
  if (!data.empty() && data.back() == '\n') data.pop_back();
  std::string out = "{\"id\":" + std::to_string(item.sequence) + ",\"sensor\":\"" + item.sensor + "\",\"type\":\"" +
                    item_type(item) + "\",\"data\":";
  out += data;
  out += '}';
  return out;
}

SettingsBody settings_from_body(std::string_view body) {
  SettingsBody parsed;
  const auto fail = [&](std::string field, std::string message) {
    parsed.error = BodyError{std::move(field), std::move(message)};
    return parsed;
  };
  const nlohmann::json json = nlohmann::json::parse(body, nullptr, false);
  if (json.is_discarded()) return fail("", "the body is not JSON: send one object of setting names and values");
  if (!json.is_object() || json.empty()) {
    return fail("", "the body must be one JSON object of setting names and values, e.g. {\"prf-hz\": 2000}");
  }
  for (const auto& [name, value] : json.items()) {
    std::string text;
    if (value.is_boolean()) {
      text = value.get<bool>() ? "on" : "off";
    } else if (value.is_number_integer()) {
      text = std::to_string(value.get<std::int64_t>());
    } else if (value.is_number()) {
      text = shortest(value.get<double>());
    } else if (value.is_string()) {
      text = value.get<std::string>();
    } else if (value.is_array()) {
      for (const auto& element : value) {
        if (!element.is_number()) return fail(name, name + ": a list holds numbers only");
        text += (text.empty() ? "" : ",") + (element.is_number_integer() ? std::to_string(element.get<std::int64_t>())
                                                                         : shortest(element.get<double>()));
      }
    } else {
      return fail(name, name + ": give a number, a string, true/false or a list of numbers");
    }
    parsed.values.emplace_back(name, std::move(text));
  }
  return parsed;
}

std::string error_json(std::string_view code, std::string_view message, std::string_view field) {
  nlohmann::json error{{"code", code}, {"message", message}};
  if (!field.empty()) error["field"] = field;
  return nlohmann::json{{"error", error}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string field_of(const Error& error, const hub::SettingValues& values) {
  for (const auto& [name, value] : values) {
    const std::string& message = error.message;
    if (message.rfind(name, 0) == 0 || message.rfind("'" + name + "'", 0) == 0 ||
        message.find(" " + name + " ") != std::string::npos || message.find("'" + name + "'") != std::string::npos) {
      return name;
    }
  }
  return "";
}

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

}  // namespace rangekit::web
