#include "mqtt/command_answer.hpp"

#include "rangekit/hub/json_views.hpp"

namespace rangekit::mqtt {

nlohmann::json answer_command(hub::Hub& hub, const std::string& sensor, CommandKind kind, std::string_view payload) {
  if (kind == CommandKind::set) {
    const hub::SettingsBody body = hub::settings_from_body(payload);
    if (body.error) return hub::error_object("bad_body", body.error->message, body.error->field);
    if (auto set = hub.set(sensor, body.values); !set) {
      return hub::error_object(hub::error_code_name(set.error().code), set.error().message,
                               hub::field_of(set.error(), body.values));
    }
    auto snapshot = hub.sensor(sensor);
    return {{"ok", true}, {"settings", snapshot ? hub::sensor_json(*snapshot)["settings"] : nlohmann::json{}}};
  }
  const hub::ActionBody body = hub::action_from_body(payload);
  if (body.error) return hub::error_object("bad_body", body.error->message, body.error->field);
  auto done = hub.act(sensor, body.action, body.argument);
  if (!done && done.error().code == Errc::unknown_command) {
    return hub::error_object("unknown_action", done.error().message, "action");
  }
  if (!done) return hub::error_object(hub::error_code_name(done.error().code), done.error().message);
  nlohmann::json answer = hub::action_json(*done);
  answer["ok"] = true;
  answer["action"] = body.action;
  return answer;
}

}  // namespace rangekit::mqtt
