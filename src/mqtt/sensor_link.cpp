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
  if (spool && qos >= 1) {
    staged.push_back(std::move(payload));
    return;
  }
  if (direct && qos == 0 && connected && queue.empty() && out.add(reading_topic, payload, max_packet)) return;
  send(Message{reading_topic, std::move(payload), qos, false});
}

void Link::store_staged() {
  if (!spool || staged.empty()) return;
  auto lost = spool->store(staged, std::chrono::system_clock::now());
  if (!lost) {
    dropped += staged.size();  // the disk refused them
    if (!std::exchange(told_spool_error, true)) {
      bridge.log("mqtt: " + config.name + ": readings not spooled (" + lost.error().message +
                 "); dropped and counted, and so are the next ones, unsaid");
    }
  } else if (*lost > 0) {
    dropped += *lost;
    if (!std::exchange(told_spool_full, true)) {
      bridge.log("mqtt: " + config.name +
                 ": spool above spool_max_mb = " + std::to_string(bridge.options.config.spool_max_mb) +
                 ": dropping the oldest readings (counted in dropped)");
    }
  }
  staged.clear();
}

void Link::publish_spooled() {
  if (!spool || !connected || out.mid_packet()) return;
  auto rows = spool->next(spool_window - std::min(spool->in_flight(), spool_window));
  if (!rows) return;  // read again at the next turn
  for (const record::SpoolRow& row : *rows) {
    int mid = 0;
    const Publish published_now =
        try_publish(Message{reading_topic, row.line, bridge.options.config.qos_reading, false}, &mid);
    if (published_now == Publish::later) break;
    if (published_now == Publish::sent) {
      spool->sent(mid, row.id);
    } else {
      spool->give_up(row.id);  // counted in dropped by try_publish
    }
  }
}

void Link::forget_acknowledged() {
  if (!spool) return;
  if (auto forgotten = spool->forget_acknowledged(); !forgotten && !std::exchange(told_spool_error, true)) {
    bridge.log("mqtt: " + config.name + ": " + forgotten.error().message);
  }
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
