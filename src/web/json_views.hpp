// The JSON the API sends and takes (docs/api.md): sensors, items, errors, and
// the settings body of a PATCH.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

#include "rangekit/hub/captures.hpp"
#include "rangekit/hub/hub.hpp"

namespace rangekit::web {

nlohmann::json sensor_json(const hub::SensorSnapshot& sensor);
// {"id":N,"sensor":"...","type":"sample"|"event","data":{...}} (data as in `stream --format jsonl`).
std::string item_json(const hub::HubItem& item);
// The event name an SSE client sees: "sample" or "event".
const char* item_type(const hub::HubItem& item);

// A PATCH body: one JSON object of name -> value (number, string, true/false, or a list
// of numbers), as text in the order given. Errors name the field.
struct BodyError {
  std::string field;
  std::string message;
};
struct SettingsBody {
  hub::SettingValues values;
  std::optional<BodyError> error;
};
SettingsBody settings_from_body(std::string_view body);

nlohmann::json capture_json(const hub::CaptureInfo& capture);

// GET /api/sensors/{name}/settings/schema of a ULS: every setting of §8's command table
// (the CLI's registry) under the name `get` prints, with the range a value must keep in
// the unit of that name, the §10 number a unit answers outside it, and the named values.
nlohmann::json uls_settings_schema();

// {"error":{"code":"out_of_range","message":"...","field":"median-points"}}
std::string error_json(std::string_view code, std::string_view message, std::string_view field = {});
// The request field an error of the hub is about: the setting its message begins with.
std::string field_of(const Error& error, const hub::SettingValues& values);

}  // namespace rangekit::web
