// The JSON the API sends and takes (docs/api.md): items and captures here; sensors,
// errors and the settings body of a PATCH from the hub, shared with the MQTT face.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

#include "rangekit/hub/captures.hpp"
#include "rangekit/hub/hub.hpp"
#include "rangekit/hub/json_views.hpp"
#include "rangekit/hub/service_family.hpp"

namespace rangekit::web {

// The JSON every face shares (sensors, settings bodies, errors) is the hub's.
using hub::BodyError;
using hub::error_json;
using hub::field_of;
using hub::sensor_json;
using hub::settings_from_body;
using hub::SettingsBody;

// {"id":N,"sensor":"...","type":"sample"|"event","data":{...}} (data as in `stream --format jsonl`),
// and a sample's "reading":{"channel","value","unit"} when it has one.
std::string item_json(const hub::HubItem& item);
// The event name an SSE client sees: "sample" or "event".
const char* item_type(const hub::HubItem& item);

nlohmann::json capture_json(const hub::CaptureInfo& capture);

}  // namespace rangekit::web
