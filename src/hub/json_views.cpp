// The faces' shared JSON (rangekit/hub/json_views.hpp): one copy, so the web face and the
// MQTT bridge read settings and report errors with the same code.
#include "rangekit/hub/json_views.hpp"

#include <array>
#include <charconv>
#include <optional>

#include "rangekit/core/family.hpp"
#include "rangekit/core/text.hpp"
#include "rangekit/record/format.hpp"

namespace rangekit::hub {
namespace {

// "12.5" and "2000" as a JSON number, or nothing.
std::optional<nlohmann::json> number_json(std::string_view text) {
  const auto number = text::parse_decimal(text);
  if (!number) return std::nullopt;
  if (text.find('.') == std::string_view::npos && text.size() < 16) return static_cast<std::int64_t>(*number);
  return *number;
}

// Numbers as JSON numbers, a list of numbers ("2000,2000,2000") as an array, as `get --json`
// prints them; everything else as the text it is.
nlohmann::json value_json(const std::string& text) {
  if (auto number = number_json(text)) return *number;
  if (text.find(',') == std::string::npos) return text;
  std::array<std::string_view, 8> parts{};
  const std::size_t count = text::split(text, ',', parts);
  if (count > parts.size()) return text;
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t i = 0; i < count; ++i) {
    auto number = number_json(parts[i]);
    if (!number) return text;
    list.push_back(*number);
  }
  return list;
}

nlohmann::json fields_json(const std::vector<Field>& fields) {
  nlohmann::json object = nlohmann::json::object();
  for (const Field& field : fields) object[field.key] = value_json(field.value);
  return object;
}

std::string shortest(double value) {
  std::array<char, 64> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return {buffer.data(), result.ptr};
}

}  // namespace

nlohmann::json sensor_json(const SensorSnapshot& sensor) {
  const SensorConfig& config = sensor.config;
  const SensorHealth& health = sensor.health;
  nlohmann::json out{{"name", config.name},
                     {"family", config.family},
                     {"port", config.port},
                     {"connected", health.connected},
                     {"streaming", sensor.streaming},
                     {"identity", fields_json(sensor.identity)},
                     {"status", fields_json(sensor.status)},
                     {"settings", fields_json(sensor.settings)},
                     {"last_id", sensor.last_sequence}};
  nlohmann::json units = nlohmann::json::object();
  for (const Field& field : sensor.settings) {
    if (!field.unit.empty()) units[field.key] = field.unit;
  }
  out["setting_units"] = units;
  // One spelling per object: the family's, as the site file and `identity` write it; the byte
  // on the wire apart, as samples carry it.
  if (config.address) {
    out["address"] = address_text_of(config.family, *config.address);
    out["address_code"] = *config.address;
  }
  if (!config.udp.empty()) out["udp"] = config.udp;
  // Quality settings from the site file; null max_speed = the family default.
  out["max_speed"] = config.max_speed_mps ? nlohmann::json(*config.max_speed_mps) : nlohmann::json(nullptr);
  out["drop_suspect"] = config.drop_suspect;
  nlohmann::json errors = nlohmann::json::object();
  for (const auto& [number, count] : health.errors_by_number) errors[std::to_string(number)] = count;
  nlohmann::json health_json{{"connected", health.connected},
                             {"rate_hz", health.rate_hz},
                             {"records", health.records},
                             {"errors", health.errors},
                             {"errors_by_number", errors},
                             {"no_signal", health.no_signal},
                             {"suspect", health.suspect},
                             {"dropped_suspect", health.dropped_suspect},
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

nlohmann::json action_json(const ActionResult& result) {
  nlohmann::json out{{"result", result.text}, {"reading", nullptr}, {"sample", nullptr}};
  if (!result.sample) return out;
  std::string line;
  record::append_jsonl(line, *result.sample);
  out["sample"] = nlohmann::json::parse(line, nullptr, false);
  if (const auto reading = reading_of(*result.sample)) {
    out["reading"] = {{"value", rounded_to(reading->value, reading->decimals)},
                      {"unit", unit_symbol(reading->channel->unit)},
                      {"channel", reading->channel->key},
                      {"quantity", quantity_name(reading->channel->quantity)}};
  }
  return out;
}

ActionBody action_from_body(std::string_view body) {
  ActionBody parsed;
  const auto fail = [&](std::string field, std::string message) {
    parsed.error = BodyError{std::move(field), std::move(message)};
    return parsed;
  };
  const nlohmann::json json = nlohmann::json::parse(body, nullptr, false);
  if (json.is_discarded()) {
    parsed.action = std::string(body);  // a bare name: start
    return parsed;
  }
  if (json.is_string()) {
    parsed.action = json.get<std::string>();
    return parsed;
  }
  if (!json.is_object()) {
    return fail("action", std::string("an action is a name (start) or an object {\"action\": \"pointer\", "
                                      "\"argument\": \"on\"}, not a JSON ") +
                              json.type_name());
  }
  for (const auto& [key, value] : json.items()) {
    if (key != "action" && key != "argument") {
      return fail(key, "'" + key + "' is not a member of an action request (action, argument)");
    }
    if (!value.is_string()) return fail(key, "'" + key + "' must be a string, not a " + value.type_name());
  }
  if (!json.contains("action")) return fail("action", "the request names no action: {\"action\": \"start\"}");
  parsed.action = json["action"].get<std::string>();
  if (json.contains("argument")) parsed.argument = json["argument"].get<std::string>();
  return parsed;
}

std::string error_code_name(Errc code) {
  std::string name = errc_name(code);
  for (char& c : name) {
    if (c == ' ') c = '_';
  }
  return name;
}

nlohmann::json error_object(std::string_view code, std::string_view message, std::string_view field) {
  nlohmann::json error{{"code", code}, {"message", message}};
  if (!field.empty()) error["field"] = field;
  return nlohmann::json{{"error", error}};
}

std::string error_json(std::string_view code, std::string_view message, std::string_view field) {
  return error_object(code, message, field).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string field_of(const Error& error, const SettingValues& values) {
  for (const auto& [name, value] : values) {
    const std::string& message = error.message;
    if (message.rfind(name, 0) == 0 || message.rfind("'" + name + "'", 0) == 0 ||
        message.find(" " + name + " ") != std::string::npos || message.find("'" + name + "'") != std::string::npos) {
      return name;
    }
  }
  return "";
}

}  // namespace rangekit::hub
