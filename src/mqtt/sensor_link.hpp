// One sensor's broker session (Link): its topics, its bounded queue of messages waiting
// for the broker, the reading fast path, and the counters stats() reads.
#pragma once

#include <mosquitto.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mqtt/bridge_impl.hpp"
#include "mqtt/packet_outbox.hpp"
#include "mqtt/reading_spool.hpp"
#include "mqtt/reading_window.hpp"
#include "rangekit/hub/site_config.hpp"

namespace rangekit::mqtt {

// A publication waiting in a link's queue.
struct Message {
  std::string topic;
  std::string payload;
  int qos = 0;
  bool retain = false;
};

struct Link {
  Bridge::Impl& bridge;
  hub::SensorConfig config;
  std::string topic;          // <base>/<sensor>
  std::string reading_topic;  // <base>/<sensor>/reading, made once
  mosquitto* client = nullptr;
  ReadingWindow window;

  // The counters stats() reads from other threads. No lock around libmosquitto: its callbacks
  // run under its own locks, and a lock of ours taken on both sides is an inversion (TSan).
  std::atomic<std::uint64_t> published{0};
  std::atomic<std::uint64_t> dropped{0};
  std::atomic<std::uint64_t> reconnects{0};
  std::atomic<std::uint64_t> queued{0};  // queue.size()
  std::atomic<bool> connected{false};
  // The broker acknowledged the set and action subscriptions of this session: only then does
  // it count as connected in stats(), so a command sent after that is heard.
  std::atomic<bool> listening{false};
  std::atomic<bool> status_now{false};  // a command changed something: status goes out at the next poll

  // Network-thread state from here on.
  std::deque<Message> queue;
  bool ever_connected = false;
  bool republish = false;      // set on connect: the retained state goes out again
  std::optional<bool> online;  // what was last said on availability
  std::chrono::steady_clock::time_point next_status{};
  std::string last_status;  // the status without its health, to see a change
  // Reconnecting: the next attempt (none planned while zero) and the backoff after it. A
  // refused session is retried quietly every config.reconnect_max_s (the log said it once).
  std::chrono::steady_clock::time_point next_attempt{};
  int backoff_s = 1;
  bool refused = false;
  // The clean stop waits for the offline message to leave.
  int offline_mid = -1;
  bool offline_acked = false;
  int subscribe_mid = -1;             // the SUBSCRIBE of set and action this session waits to see acknowledged
  bool told_refused_message = false;  // a message libmosquitto will never take was logged
  // Since when part of a fast-path packet has waited on the wire (keepalive is held off meanwhile).
  std::chrono::steady_clock::time_point mid_packet_since{};
  bool disconnect_sent = false;  // the clean stop's DISCONNECT went to libmosquitto

  // The reading fast path (docs/mqtt.md): QoS 0 readings on a plain TCP session are encoded
  // here and written with one send() per drain. The socket is shared with libmosquitto, so
  // packets never interleave: ours go only when libmosquitto has nothing pending
  // (mosquitto_want_write), and while part of ours is on the wire (mid_packet) no
  // libmosquitto call that may write is made (publish, read, misc, write, disconnect).
  bool direct = false;           // plain TCP and a reading topic libmosquitto would accept too
  std::uint32_t max_packet = 0;  // the broker's Maximum Packet Size (CONNACK, MQTT 5), 0: none
  PacketOutbox out;

  // [mqtt] spool: QoS >= 1 readings are staged here, stored on disk once per turn of the
  // network loop, and published from the spool with at most spool_window in flight.
  std::unique_ptr<ReadingSpool> spool;
  std::vector<std::string> staged;
  static constexpr std::size_t spool_window = 100;
  bool told_spool_full = false;
  bool told_spool_error = false;

  Link(Bridge::Impl& b, hub::SensorConfig c)
      : bridge(b),
        config(std::move(c)),
        topic(b.options.config.base_topic + "/" + config.name),
        reading_topic(topic + "/reading"),
        window(b.options.config.max_rate_hz),
        backoff_s(std::max(b.options.reconnect_min_s, 1)) {}

  // Never waits for the broker: when the session is down the message waits in the
  // bounded queue, and a full queue loses its oldest message (counted).
  void send(Message message);

  enum class Publish {
    sent,     // handed to libmosquitto (written, or queued in the session until the socket takes it)
    later,    // not now (no connection): keep it
    refused,  // never: too large for the broker, or a topic or text libmosquitto rejects (dropped, counted)
  };
  // On the network thread: without libmosquitto's thread the packet is written here and then,
  // or queued in the session until the socket can take it.
  Publish try_publish(const Message& message, int* mid = nullptr);

  // A reading: by the fast path when it can (QoS 0, connected, nothing queued before it),
  // else as any message.
  void send_reading(std::string payload, int qos);

  // [mqtt] spool: the staged readings to disk, then as many spooled readings out as the window allows.
  void store_staged();
  void publish_spooled();
  // The acknowledged readings leave the disk.
  void forget_acknowledged();

  // Writes out as far as the socket takes it (nonblocking), after anything libmosquitto has pending.
  void write_out();

  // What out still holds will not reach the broker (a lost connection): counted as dropped.
  void drop_out() { dropped += out.drop(); }

  // Sends what waited, oldest first. After a (re)connect its retained messages are stale (the
  // fresh state goes out next) and are left out.
  void flush(bool drop_retained);
};

}  // namespace rangekit::mqtt
