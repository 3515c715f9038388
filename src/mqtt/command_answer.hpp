// The answer to one `set` or `action` command, as the bridge publishes it on `.../result`:
// the body read as the HTTP API reads it, then the hub's own checks. Any payload, of any
// JSON type or none, gets an object with "ok" or "error"; nothing throws.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

#include "rangekit/hub/hub.hpp"

namespace rangekit::mqtt {

enum class CommandKind { set, action };

nlohmann::json answer_command(hub::Hub& hub, const std::string& sensor, CommandKind kind, std::string_view payload);

}  // namespace rangekit::mqtt
