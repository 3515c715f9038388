// Home Assistant MQTT discovery: the retained config messages that describe one sensor's
// entities (distance, presence, rate, device errors) to Home Assistant.
#pragma once

#include <vector>

#include "mqtt/sensor_link.hpp"
#include "rangekit/hub/site_config.hpp"

namespace rangekit::mqtt {

// One retained config message per entity, under config.discovery_prefix.
std::vector<Message> discovery_messages(const Link& link, const hub::MqttConfig& config);

}  // namespace rangekit::mqtt
