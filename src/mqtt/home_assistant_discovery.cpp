// Home Assistant MQTT discovery: one retained config message per entity of a sensor,
// its entities taken from the sensor family's channels.
#include "mqtt/home_assistant_discovery.hpp"

#include <nlohmann/json.hpp>

#include <cctype>
#include <string>
#include <vector>

#include "rangekit/core/family.hpp"
#include "rangekit/hub/service_family.hpp"

namespace rangekit::mqtt {
namespace {

std::string discovery_device(const Link& link, const hub::MqttConfig& config, nlohmann::json& out) {
  const hub::ServiceFamily& service = *hub::find_service_family(link.config.family);
  std::string id = config.client_id + "_" + link.config.name;
  out["device"] = {{"identifiers", {id}},
                   {"name", link.config.name},
                   {"manufacturer", service.manufacturer},
                   {"model", service.model},
                   {"via_device", config.client_id}};
  out["availability_topic"] = link.topic + "/availability";
  out["payload_available"] = "online";
  out["payload_not_available"] = "offline";
  return id;
}

}  // namespace

std::vector<Message> discovery_messages(const Link& link, const hub::MqttConfig& config) {
  std::vector<Message> out;
  const auto entity = [&](const char* component, const char* object, nlohmann::json body) {
    const std::string id = discovery_device(link, config, body);
    body["unique_id"] = id + "_" + object;
    body["object_id"] = id + "_" + object;
    out.push_back(Message{config.discovery_prefix + "/" + component + "/" + id + "/" + object + "/config", body.dump(),
                          config.qos_state, true});
  };
  // From the family's channels: its first distance, and its presence if it has one.
  const FamilyDescriptor* family = find_family(link.config.family);
  const auto channel_of = [family](Quantity quantity) -> const ChannelDescriptor* {
    if (family == nullptr) return nullptr;
    const auto index = channel_index(*family, quantity);
    return index ? &family->channels[*index] : nullptr;
  };
  if (const ChannelDescriptor* distance = channel_of(Quantity::distance)) {
    // A window carries "last" in its reading's unit (a look-down window's is a presence, no
    // distance); a sample its own distance field (null without a signal).
    const std::string unit = unit_symbol(distance->unit);
    entity("sensor", "distance",
           {{"name", "Distance"},
            {"state_topic", link.topic + "/reading"},
            {"value_template", "{{ (value_json.last if value_json.unit == '" + unit +
                                   "' else none) if value_json.window is defined else value_json." +
                                   std::string(distance->key) + " }}"},
            {"unit_of_measurement", unit},
            {"device_class", "distance"},
            {"state_class", "measurement"}});
  }
  if (const ChannelDescriptor* presence = channel_of(Quantity::presence)) {
    entity("binary_sensor", "presence",
           {{"name", "Presence"},
            {"state_topic", link.topic + "/reading"},
            {"value_template", "{{ 'ON' if value_json." + std::string(presence->key) + " else 'OFF' }}"},
            {"device_class", "presence"}});
  }
  // A button per action and argument, pressing publishes the action request on the action topic.
  for (const hub::ActionDescriptor* action : hub::actions_of(link.config.family)) {
    std::vector<std::string_view> arguments(action->arguments.begin(), action->arguments.end());
    if (arguments.empty() || action->argument_optional) arguments.insert(arguments.begin(), std::string_view());
    for (const std::string_view argument : arguments) {
      std::string label(action->name);
      label[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(label[0])));
      nlohmann::json press{{"action", action->name}};
      std::string object = "action_" + std::string(action->name);
      if (!argument.empty()) {
        press["argument"] = argument;
        label += " " + std::string(argument);
        object += "_" + std::string(argument);
      }
      entity("button", object.c_str(),
             {{"name", label},
              {"command_topic", link.topic + "/action"},
              {"payload_press", press.dump()},
              {"entity_category", "config"}});
    }
  }
  entity("sensor", "rate",
         {{"name", "Rate"},
          {"state_topic", link.topic + "/status"},
          {"value_template", "{{ value_json.health.rate_hz }}"},
          {"unit_of_measurement", "Hz"},
          {"entity_category", "diagnostic"},
          {"state_class", "measurement"}});
  entity("sensor", "errors",
         {{"name", "Device errors"},
          {"state_topic", link.topic + "/status"},
          {"value_template", "{{ value_json.health.errors }}"},
          {"entity_category", "diagnostic"},
          {"state_class", "total_increasing"}});
  return out;
}

}  // namespace rangekit::mqtt
