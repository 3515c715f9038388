// The JSON every face of the hub sends and takes (docs/api.md, docs/mqtt.md): a
// sensor's snapshot, the settings body of an HTTP PATCH or an MQTT `set`, and
// errors. One copy for all faces, so a setting is read the same way whichever
// way it arrives, and then checked by the hub against the CLI's tables.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <string_view>

#include "rangekit/hub/hub.hpp"

namespace rangekit::hub {

nlohmann::json sensor_json(const SensorSnapshot& sensor);

// A settings body: one JSON object of name -> value (number, string, true/false, or a list
// of numbers), as text in the order given. Errors name the field.
struct BodyError {
  std::string field;
  std::string message;
};
struct SettingsBody {
  SettingValues values;
  std::optional<BodyError> error;
};
SettingsBody settings_from_body(std::string_view body);

// An action request as MQTT carries it: a bare name (start), a JSON string ("start"), or an
// object {"action": "pointer", "argument": "on"} whose members are strings. Errors name the field.
struct ActionBody {
  std::string action;
  std::string argument;
  std::optional<BodyError> error;
};
ActionBody action_from_body(std::string_view body);
// An action's answer: {"result": text, "reading": {"value", "unit", "channel", "quantity"} or
// null, "sample": the measurement as a stream line gives it, or null}.
nlohmann::json action_json(const ActionResult& result);

// "out of range" -> "out_of_range": one word a client can switch on.
std::string error_code_name(Errc code);
// {"error":{"code":"out_of_range","message":"...","field":"median-points"}}
nlohmann::json error_object(std::string_view code, std::string_view message, std::string_view field = {});
std::string error_json(std::string_view code, std::string_view message, std::string_view field = {});
// The request field an error of the hub is about: the setting its message begins with.
std::string field_of(const Error& error, const SettingValues& values);

}  // namespace rangekit::hub
