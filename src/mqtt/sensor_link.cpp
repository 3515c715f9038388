// How one sensor's session publishes: at once when it can, else through its bounded queue,
// and its readings by the fast path's own packets on the shared socket.
#include "mqtt/sensor_link.hpp"

namespace rangekit::mqtt {

void Link::send(Message message) {
  if (connected && queue.empty() && !out.mid_packet() && try_publish(message) != Publish::later) return;
  queue.push_back(std::move(message));
  while (queue.size() > bridge.options.config.queue_limit) {
    queue.pop_front();
    ++dropped;
  }
  queued = queue.size();
}

Link::Publish Link::try_publish(const Message& message, int* mid) {
  const int rc = mosquitto_publish(client, mid, message.topic.c_str(), static_cast<int>(message.payload.size()),
                                   message.payload.data(), message.qos, message.retain);
  if (rc == MOSQ_ERR_SUCCESS) {
    ++published;
    return Publish::sent;
  }
  if (rc != MOSQ_ERR_OVERSIZE_PACKET && rc != MOSQ_ERR_PAYLOAD_SIZE && rc != MOSQ_ERR_INVAL &&
      rc != MOSQ_ERR_MALFORMED_UTF8 && rc != MOSQ_ERR_QOS_NOT_SUPPORTED && rc != MOSQ_ERR_NOT_SUPPORTED) {
    return Publish::later;
  }
  // Kept, it would hold up every message behind it in the queue for good.
  ++dropped;
  if (!told_refused_message) {
    told_refused_message = true;
    bridge.log("mqtt: " + message.topic + ": the message cannot be published (" + mosquitto_strerror(rc) +
               (rc == MOSQ_ERR_OVERSIZE_PACKET ? ", larger than the broker's maximum packet size" : "") +
               "); dropped and counted, and so are the next such ones, unsaid");
  }
  return Publish::refused;
}

void Link::send_reading(std::string payload, int qos) {
  if (direct && qos == 0 && connected && queue.empty() && out.add(reading_topic, payload, max_packet)) return;
  send(Message{reading_topic, std::move(payload), qos, false});
}

void Link::write_out() {
  const int sock = mosquitto_socket(client);
  if (out.empty() || sock < 0) return;
  if (!out.mid_packet() && mosquitto_want_write(client)) return;  // its packet first (POLLOUT)
  // A failed write means the connection is gone: libmosquitto's next read finds out and reconnects.
  if (out.write_to(sock) == PacketOutbox::Write::failed) drop_out();
  published += out.take_completed();
}

void Link::flush(bool drop_retained) {
  // After the fast path's packets: a reading queued behind them must not overtake them.
  while (!queue.empty() && connected && out.empty()) {
    if (!(drop_retained && queue.front().retain) && try_publish(queue.front()) == Publish::later) break;
    queue.pop_front();
  }
  queued = queue.size();
}

}  // namespace rangekit::mqtt
