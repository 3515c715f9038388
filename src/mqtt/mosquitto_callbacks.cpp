// libmosquitto's callbacks for each sensor's session, and what the bridge makes of a
// connect, a SUBACK or a loss: backoff, the connected count and the lines it logs.
#include "mqtt/mosquitto_callbacks.hpp"

#include <mqtt_protocol.h>

#include <algorithm>
#include <cstdint>
#include <mutex>
#include <string>

#include "mqtt/bridge_impl.hpp"
#include "mqtt/sensor_link.hpp"

namespace rangekit::mqtt {
namespace {

// MQTT 5 CONNACK reason codes (and their MQTT 3.1.1 counterparts 4 and 5) that retrying will not fix.
bool refused_credentials(int reason) {
  return reason == MQTT_RC_BAD_USERNAME_OR_PASSWORD || reason == MQTT_RC_NOT_AUTHORIZED ||
         reason == CONNACK_REFUSED_BAD_USERNAME_PASSWORD || reason == CONNACK_REFUSED_NOT_AUTHORIZED;
}

void on_connect(mosquitto* /*client*/, void* user, int reason, int /*flags*/, const mosquitto_property* props) {
  auto* link = static_cast<Link*>(user);
  // A broker may limit the packets it takes (MQTT 5 §3.2.2.3.6); libmosquitto checks its own
  // publishes against it, and the fast path must too.
  std::uint32_t max_packet = 0;
  if (mosquitto_property_read_int32(props, MQTT_PROP_MAXIMUM_PACKET_SIZE, &max_packet, false) == nullptr) {
    max_packet = 0;
  }
  link->max_packet = max_packet;
  link->bridge.on_connected(*link, reason);
}

void on_disconnect(mosquitto* /*client*/, void* user, int reason, const mosquitto_property* /*props*/) {
  auto* link = static_cast<Link*>(user);
  link->bridge.on_lost(*link, reason);
}

void on_subscribe(mosquitto* /*client*/, void* user, int mid, int count, const int* granted,
                  const mosquitto_property* /*props*/) {
  auto* link = static_cast<Link*>(user);
  link->bridge.on_subscribed(*link, mid, count, granted);
}

void on_publish(mosquitto* /*client*/, void* user, int mid, int /*reason*/, const mosquitto_property* /*props*/) {
  auto* link = static_cast<Link*>(user);
  if (mid == link->offline_mid) link->offline_acked = true;
  if (link->spool) link->spool->acknowledged(mid);
}

void on_message(mosquitto* /*client*/, void* user, const mosquitto_message* message, const mosquitto_property* props) {
  auto* link = static_cast<Link*>(user);
  link->bridge.receive_command(*link, *message, props);
}

}  // namespace

void set_session_callbacks(mosquitto* client) {
  mosquitto_connect_v5_callback_set(client, on_connect);
  mosquitto_disconnect_v5_callback_set(client, on_disconnect);
  mosquitto_publish_v5_callback_set(client, on_publish);
  mosquitto_subscribe_v5_callback_set(client, on_subscribe);
  mosquitto_message_v5_callback_set(client, on_message);
}

void Bridge::Impl::on_connected(Link& link, int reason) {
  if (reason != 0) {
    ++refusals;
    link.refused = true;
    const std::lock_guard lock(state_mutex);
    if (refused_credentials(reason)) {
      error = "broker " + options.config.broker + " refused the credentials" +
              (options.config.username.empty() ? std::string(" (none given)")
                                               : " of user '" + options.config.username + "'") +
              ": " + mosquitto_reason_string(reason) + "; check [mqtt] username and password";
      if (!told_refused) log("mqtt: " + error);  // once: the retries behind it say nothing more
      told_refused = true;
    } else if (!told_down) {
      log("mqtt: broker " + options.config.broker + " refused the connection: " + mosquitto_reason_string(reason) +
          "; retrying");
      told_down = true;
    }
    return;
  }
  link.backoff_s = std::max(options.reconnect_min_s, 1);
  if (link.spool) {
    // A fresh session: what was in flight and not acknowledged goes again from the spool.
    link.forget_acknowledged();
    link.spool->resend_in_flight();
  }
  subscribe_commands(link);
  if (link.ever_connected) ++link.reconnects;
  link.ever_connected = true;
  link.connected = true;
  link.republish = true;  // the callback runs on the network thread
  const std::lock_guard lock(state_mutex);
  error.clear();
  told_refused = false;
}

void Bridge::Impl::on_subscribed(Link& link, int mid, int count, const int* granted) {
  if (mid != link.subscribe_mid || !link.connected || link.listening.exchange(true)) return;
  for (int i = 0; i < count; ++i) {
    if (granted[i] >= 0x80) {  // MQTT 5 reason codes from 0x80 are failures (e.g. not authorised)
      log("mqtt: broker " + options.config.broker + " refused the subscription to " + link.topic +
          (i == 0 ? "/set" : "/action") + ": " + mosquitto_reason_string(granted[i]) + "; commands will not be heard");
    }
  }
  const int now_connected = ++connected_links;
  const std::lock_guard lock(state_mutex);
  if (now_connected == static_cast<int>(links.size())) {
    log("mqtt: connected to " + options.config.broker + " as " + options.config.client_id + "-* (" +
        std::to_string(links.size()) + " sensors under " + options.config.base_topic + "/)");
    told_down = false;
  }
}

void Bridge::Impl::on_lost(Link& link, int reason) {
  link.drop_out();
  if (!link.connected.exchange(false)) return;
  if (link.listening.exchange(false)) --connected_links;
  if (stopping || reason == 0) return;
  const std::lock_guard lock(state_mutex);
  if (!told_down) {
    log("mqtt: lost the broker " + options.config.broker + " (" + mosquitto_strerror(reason) + "); queueing up to " +
        std::to_string(options.config.queue_limit) + " messages per sensor and reconnecting with backoff");
    told_down = true;
  }
}

}  // namespace rangekit::mqtt
