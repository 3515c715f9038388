// One libmosquitto session per sensor, so that each sensor's availability topic can
// carry its own will ("offline", retained) and the broker marks every sensor offline
// when the service dies. One network thread of ours drives every session (no
// libmosquitto thread): it waits in one poll() on the hub's bounded subscription and on
// every session's socket, turns hub items into messages and publishes them itself, so a
// publish is a write() on this thread that wakes no other (with a libmosquitto thread
// per session, each publish woke that thread through its socketpair: perf, docs/mqtt.md).
// QoS 0 readings skip mosquitto_publish: each drain's are encoded here and leave in one
// send() per session (the fast path, Link::out), and while they flow the thread drains
// the hub on a timer (BridgeOptions::drain_gather) instead of at every wake-up.
// libmosquitto is not thread-safe per session without its own thread, so every call for
// a session happens on the network thread, which also reconnects with exponential
// backoff. A command thread runs `set` and `action` requests, which wait for the sensor,
// and hands their results back to the network thread through a queue.
#include "rangekit/mqtt/bridge.hpp"

#include <mosquitto.h>
#include <mqtt_protocol.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <thread>

#include "mqtt/command_answer.hpp"
#include "mqtt/packet_outbox.hpp"
#include "mqtt/reading_window.hpp"
#include "rangekit/core/family.hpp"
#include "rangekit/hub/json_views.hpp"
#include "rangekit/hub/service_family.hpp"

namespace rangekit::mqtt {

// A publication waiting in a link's queue (outside the anonymous namespace, as Link is).
struct Message {
  std::string topic;
  std::string payload;
  int qos = 0;
  bool retain = false;
};

namespace {

using namespace std::chrono_literals;

// MQTT 5 CONNACK reason codes (and their MQTT 3.1.1 counterparts 4 and 5) that retrying will not fix.
bool refused_credentials(int reason) {
  return reason == MQTT_RC_BAD_USERNAME_OR_PASSWORD || reason == MQTT_RC_NOT_AUTHORIZED ||
         reason == CONNACK_REFUSED_BAD_USERNAME_PASSWORD || reason == CONNACK_REFUSED_NOT_AUTHORIZED;
}

void init_library() {
  static std::once_flag once;
  std::call_once(once, [] { mosquitto_lib_init(); });
}

}  // namespace

struct Link;

struct Command {
  Link* link = nullptr;
  bool is_set = true;  // set, else action
  std::string payload;
  std::string response_topic;  // MQTT 5
  std::string correlation;     // MQTT 5 correlation data, as bytes
  // Set when the message is answered with this error and not run.
  struct Refusal {
    std::string code;
    std::string message;
    std::string field;
  };
  std::optional<Refusal> refusal;
};

// A command is a few settings or one action name; anything longer is refused unread and not queued.
constexpr std::size_t max_command_bytes = std::size_t{16} * 1024;

// The network thread's eventfd. Shared with the hub's listener, which the hub may still be
// calling while the bridge stops: the fd closes when the last holder lets go, so a late
// wake-up never writes to a closed (or reused) descriptor.
struct WakeFd {
  int fd = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  WakeFd() = default;
  ~WakeFd() {
    if (fd >= 0) ::close(fd);
  }
  WakeFd(const WakeFd&) = delete;
  WakeFd& operator=(const WakeFd&) = delete;
  void signal() const {
    const std::uint64_t one = 1;
    if (::write(fd, &one, sizeof one) < 0) return;  // full counter: a wake-up is pending anyway
  }
};

// A command's result, published by the network thread.
struct Reply {
  Link* link = nullptr;
  std::string topic;
  std::string payload;
  std::string response_topic;  // MQTT 5
  std::string correlation;
};

struct Bridge::Impl {
  hub::Hub& hub;
  BridgeOptions options;
  hub::BrokerAddress address;
  std::vector<std::unique_ptr<Link>> links;
  std::map<std::string, Link*, std::less<>> by_sensor;

  std::atomic<bool> stopping{false};  // the command thread ends
  std::atomic<bool> closing{false};   // the network thread says offline, disconnects and ends
  // Hub items, replies or closing for the network thread.
  std::shared_ptr<const WakeFd> waker = std::make_shared<const WakeFd>();
  std::thread network;
  std::thread commander;
  std::mutex command_mutex;
  std::condition_variable command_ready;
  std::deque<Command> commands;
  std::mutex reply_mutex;
  std::deque<Reply> replies;

  mutable std::mutex state_mutex;  // error, logged flags
  std::string error;
  bool told_refused = false;
  bool told_down = false;
  std::atomic<int> connected_links{0};
  std::atomic<std::uint64_t> hub_lost{0};
  std::atomic<std::uint64_t> handled{0};
  std::atomic<std::uint64_t> busy{0};
  std::atomic<std::uint64_t> refusals{0};

  Impl(hub::Hub& h, BridgeOptions o) : hub(h), options(std::move(o)) {}
  ~Impl();
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  void log(const std::string& line) const {
    if (options.log) options.log(line);
  }
  void wake() const { waker->signal(); }
  void run_network();
  bool serve_sockets(std::chrono::microseconds timeout, bool hear_wake = true);
  template <class Pending>
  void serve_while(Pending pending, std::chrono::milliseconds limit);
  std::size_t take_items(hub::Subscription& subscription);
  void send_replies();
  void poll_sensors(std::chrono::steady_clock::time_point now);
  void keep_connected(Link& link, std::chrono::steady_clock::time_point now) const;
  void say_offline_and_disconnect();
  void run_commands();
  void handle(Command& command);
  // Queues the command's answer for the network thread: on its result topic, and on its
  // response topic when it named one.
  void answer(Command& command, nlohmann::json result);
  nlohmann::json result_of(const Command& command);
  void on_connected(Link& link, int reason);
  void on_subscribed(Link& link, int mid, int count, const int* granted);
  void on_lost(Link& link, int reason);
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

  Link(Bridge::Impl& b, hub::SensorConfig c)
      : bridge(b),
        config(std::move(c)),
        topic(b.options.config.base_topic + "/" + config.name),
        reading_topic(topic + "/reading"),
        window(b.options.config.max_rate_hz),
        backoff_s(std::max(b.options.reconnect_min_s, 1)) {}

  // Never waits for the broker: when the session is down the message waits in the
  // bounded queue, and a full queue loses its oldest message (counted).
  void send(Message message) {
    if (connected && queue.empty() && !out.mid_packet() && try_publish(message) != Publish::later) return;
    queue.push_back(std::move(message));
    while (queue.size() > bridge.options.config.queue_limit) {
      queue.pop_front();
      ++dropped;
    }
    queued = queue.size();
  }

  enum class Publish {
    sent,     // handed to libmosquitto (written, or queued in the session until the socket takes it)
    later,    // not now (no connection): keep it
    refused,  // never: too large for the broker, or a topic or text libmosquitto rejects (dropped, counted)
  };
  // On the network thread: without libmosquitto's thread the packet is written here and then,
  // or queued in the session until the socket can take it.
  Publish try_publish(const Message& message, int* mid = nullptr) {
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

  // A reading: by the fast path when it can (QoS 0, connected, nothing queued before it),
  // else as any message.
  void send_reading(std::string payload, int qos) {
    if (direct && qos == 0 && connected && queue.empty() && out.add(reading_topic, payload, max_packet)) return;
    send(Message{reading_topic, std::move(payload), qos, false});
  }

  // Writes out as far as the socket takes it (nonblocking), after anything libmosquitto has pending.
  void write_out() {
    const int sock = mosquitto_socket(client);
    if (out.empty() || sock < 0) return;
    if (!out.mid_packet() && mosquitto_want_write(client)) return;  // its packet first (POLLOUT)
    // A failed write means the connection is gone: libmosquitto's next read finds out and reconnects.
    if (out.write_to(sock) == PacketOutbox::Write::failed) drop_out();
    published += out.take_completed();
  }

  // What out still holds will not reach the broker (a lost connection): counted as dropped.
  void drop_out() { dropped += out.drop(); }

  // Sends what waited, oldest first. After a (re)connect its retained messages are stale (the
  // fresh state goes out next) and are left out.
  void flush(bool drop_retained) {
    // After the fast path's packets: a reading queued behind them must not overtake them.
    while (!queue.empty() && connected && out.empty()) {
      if (!(drop_retained && queue.front().retain) && try_publish(queue.front()) == Publish::later) break;
      queue.pop_front();
    }
    queued = queue.size();
  }
};

namespace {

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
}

void on_message(mosquitto* /*client*/, void* user, const mosquitto_message* message, const mosquitto_property* props) {
  auto* link = static_cast<Link*>(user);
  Command command;
  command.link = link;
  const std::string topic = message->topic;
  if (topic == link->topic + "/set") {
    command.is_set = true;
  } else if (topic == link->topic + "/action") {
    command.is_set = false;
  } else {
    return;
  }
  const auto size = static_cast<std::size_t>(std::max(message->payloadlen, 0));
  const auto refuse = [&](std::string code, std::string why, std::string field = {}) {
    command.refusal = Command::Refusal{std::move(code), std::move(why), std::move(field)};
  };
  if (message->retain) {
    // A retained command would run again at every connect of every service that subscribes.
    refuse("retained",
           "a retained command is not run: publish it without the retain flag, and clear the retained one with an "
           "empty retained message to " +
               topic);
  } else if (size > max_command_bytes) {
    refuse("too_large", "a command of " + std::to_string(size) + " bytes is not run: at most " +
                            std::to_string(max_command_bytes) + " bytes");
  } else if (size > 0) {
    command.payload.assign(static_cast<const char*>(message->payload), size);
  }
  char* response = nullptr;
  if (mosquitto_property_read_string(props, MQTT_PROP_RESPONSE_TOPIC, &response, false) != nullptr &&
      response != nullptr) {
    command.response_topic = response;
    free(response);  // NOLINT(cppcoreguidelines-no-malloc): libmosquitto allocates it with malloc
  }
  // Answers go out under the service's own rights, so only to topics made for them.
  if (const std::string replies = link->bridge.options.config.base_topic + "/reply/";
      !command.response_topic.empty() && !command.response_topic.starts_with(replies)) {
    if (!command.refusal) {
      refuse("bad_response_topic",
             "the response topic '" + command.response_topic + "' is not under " + replies + ": nothing was run",
             "response_topic");
    }
    command.response_topic.clear();
  }
  void* correlation = nullptr;
  std::uint16_t length = 0;
  if (mosquitto_property_read_binary(props, MQTT_PROP_CORRELATION_DATA, &correlation, &length, false) != nullptr &&
      correlation != nullptr) {
    command.correlation.assign(static_cast<const char*>(correlation), length);
    free(correlation);  // NOLINT(cppcoreguidelines-no-malloc)
  }
  Bridge::Impl& bridge = link->bridge;
  bool queued = false;
  {
    const std::lock_guard lock(bridge.command_mutex);
    if (bridge.commands.size() < bridge.options.max_queued_commands) {
      bridge.commands.push_back(std::move(command));
      queued = true;
    }
  }
  if (queued) {
    bridge.command_ready.notify_one();
    return;
  }
  // A flood of commands is not queued without end: the one over the bound is answered now.
  ++bridge.busy;
  bridge.answer(command, hub::error_object("busy", std::to_string(bridge.options.max_queued_commands) +
                                                       " commands are waiting already: this one was not run; "
                                                       "send it again once they are answered"));
}

}  // namespace

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
  // Both command topics in one SUBSCRIBE: the session counts as connected at its SUBACK.
  const std::string set_topic = link.topic + "/set";
  const std::string action_topic = link.topic + "/action";
  std::array<char*, 2> topics{const_cast<char*>(set_topic.c_str()), const_cast<char*>(action_topic.c_str())};
  link.subscribe_mid = -1;
  // Retained commands are never sent to it (MQTT 5 retain handling 2): they would run at every connect.
  mosquitto_subscribe_multiple(link.client, &link.subscribe_mid, static_cast<int>(topics.size()), topics.data(),
                               options.config.qos_command, MQTT_SUB_OPT_SEND_RETAIN_NEVER, nullptr);
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

// Home Assistant MQTT discovery: one retained config message per entity.
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
    for (const ChannelDescriptor& channel : family->channels) {
      if (channel.quantity == quantity) return &channel;
    }
    return nullptr;
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

}  // namespace

// One poll over the wake eventfd and every open session socket, then libmosquitto's read
// and write for the sockets that are ready (its callbacks run here, on the network thread).
// True when the eventfd woke it (hub items, replies or closing); not heard when !hear_wake.
bool Bridge::Impl::serve_sockets(std::chrono::microseconds timeout, bool hear_wake) {
  std::vector<pollfd> fds;
  std::vector<Link*> owners;
  fds.reserve(links.size() + 1);
  owners.reserve(links.size());
  fds.push_back(pollfd{waker->fd, static_cast<short>(hear_wake ? POLLIN : 0), 0});
  for (const auto& link : links) {
    const int sock = mosquitto_socket(link->client);
    if (sock < 0) continue;
    // While part of a fast-path packet is on the wire only its rest may go (Link::out).
    const bool write = mosquitto_want_write(link->client) || !link->out.empty();
    const auto events = static_cast<short>((link->out.mid_packet() ? 0 : POLLIN) | (write ? POLLOUT : 0));
    fds.push_back(pollfd{sock, events, 0});
    owners.push_back(link.get());
  }
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(timeout);
  const timespec wait{seconds.count(), std::chrono::duration_cast<std::chrono::nanoseconds>(timeout - seconds).count()};
  if (::ppoll(fds.data(), fds.size(), &wait, nullptr) <= 0) return false;
  const bool woken = (fds[0].revents & POLLIN) != 0;
  if (woken) {
    std::uint64_t count = 0;
    if (::read(waker->fd, &count, sizeof count) < 0) count = 0;  // nonblocking: nothing to take is fine
  }
  for (std::size_t i = 0; i < owners.size(); ++i) {
    const short revents = fds[i + 1].revents;
    Link& link = *owners[i];
    mosquitto* client = link.client;
    if ((revents & (POLLERR | POLLHUP)) != 0) link.drop_out();  // lost: libmosquitto's read says so
    if ((revents & (POLLIN | POLLERR | POLLHUP)) != 0 && !link.out.mid_packet()) mosquitto_loop_read(client, 1);
    if ((revents & POLLOUT) != 0 && mosquitto_socket(client) >= 0) {
      if (!link.out.mid_packet() && mosquitto_want_write(client)) mosquitto_loop_write(client, 1);
      link.write_out();
    }
  }
  return woken;
}

std::size_t Bridge::Impl::take_items(hub::Subscription& subscription) {
  const hub::MqttConfig& config = options.config;
  std::size_t total = 0;
  // The listener wakes this thread only when an item lands in an empty queue: take it all.
  for (std::size_t taken = 1024; taken == 1024;) {
    const auto batch = subscription.take(1024, 0ms);
    taken = batch.size();
    total += taken;
    for (const hub::HubItemPtr& item : batch) {
      const auto found = by_sensor.find(item->sensor);
      if (found == by_sensor.end()) continue;
      Link& link = *found->second;
      if (const auto* sample = std::get_if<Sample>(&item->item)) {
        if (auto message = link.window.add(*sample, std::chrono::steady_clock::now())) {
          link.send_reading(std::move(*message), config.qos_reading);
        }
      } else if (const auto* event = std::get_if<StreamEvent>(&item->item);
                 event != nullptr && event->kind == StreamEventKind::lost_records) {
        link.window.add_lost(event->count);
      }
    }
  }
  hub_lost = subscription.lost();
  return total;
}

void Bridge::Impl::send_replies() {
  std::deque<Reply> ready;
  {
    const std::lock_guard lock(reply_mutex);
    ready.swap(replies);
  }
  const int qos = options.config.qos_command;
  std::deque<Reply> later;  // a session with part of a fast-path packet on the wire writes nothing else
  for (Reply& reply : ready) {
    Link& link = *reply.link;
    if (link.out.mid_packet()) {
      later.push_back(std::move(reply));
      continue;
    }
    if (!reply.response_topic.empty()) {
      // MQTT 5 request/response: the answer on the asked topic, with the request's correlation data.
      mosquitto_property* props = nullptr;
      if (!reply.correlation.empty()) {
        mosquitto_property_add_binary(&props, MQTT_PROP_CORRELATION_DATA, reply.correlation.data(),
                                      static_cast<std::uint16_t>(reply.correlation.size()));
      }
      if (link.connected && mosquitto_publish_v5(link.client, nullptr, reply.response_topic.c_str(),
                                                 static_cast<int>(reply.payload.size()), reply.payload.data(), qos,
                                                 false, props) == MOSQ_ERR_SUCCESS) {
        ++link.published;
      }
      mosquitto_property_free_all(&props);
    }
    link.send(Message{std::move(reply.topic), std::move(reply.payload), qos, false});
  }
  if (later.empty()) return;
  const std::lock_guard lock(reply_mutex);
  for (auto it = later.rbegin(); it != later.rend(); ++it) replies.push_front(std::move(*it));
}

// Without libmosquitto's thread the bridge keeps each session up itself: keepalive (PINGREQ,
// and a silent broker counted as lost), and a reconnect with backoff doubling from
// reconnect_min_s to reconnect_max_s, or every reconnect_max_s after a refusal.
void Bridge::Impl::keep_connected(Link& link, std::chrono::steady_clock::time_point now) const {
  if (const int sock = mosquitto_socket(link.client); sock >= 0) {
    if (!link.out.mid_packet()) {
      link.mid_packet_since = {};
      mosquitto_loop_misc(link.client);  // keepalive; it may write a PINGREQ
      return;
    }
    // No PINGREQ can go while part of a packet waits, so libmosquitto's keepalive cannot see a
    // broker that stopped reading (a dead host, no RST). A socket that takes nothing more for
    // 1.5 keepalive periods is taken for lost, as libmosquitto would: shut down, its next read
    // reports the loss and the session reconnects.
    if (link.mid_packet_since == std::chrono::steady_clock::time_point{}) link.mid_packet_since = now;
    if (now - link.mid_packet_since > std::chrono::milliseconds(1500) * std::max(options.keepalive_s, 1)) {
      ::shutdown(sock, SHUT_RDWR);
      link.mid_packet_since = {};
    }
    return;
  }
  if (link.next_attempt == std::chrono::steady_clock::time_point{}) {
    const int max_s = std::max(options.config.reconnect_max_s, 1);
    const int delay_s = link.refused ? max_s : std::min(link.backoff_s, max_s);
    if (!link.refused) link.backoff_s = std::min(link.backoff_s * 2, max_s);
    link.refused = false;
    link.next_attempt = now + std::chrono::seconds(delay_s);
    return;
  }
  if (now < link.next_attempt) return;
  link.next_attempt = {};
  // A broker still away fails here or on the socket; the next call plans the next attempt.
  mosquitto_reconnect_async(link.client);
}

// Availability follows the sensor's link; status goes out on a change and every status_interval.
void Bridge::Impl::poll_sensors(std::chrono::steady_clock::time_point now) {
  const hub::MqttConfig& config = options.config;
  for (const auto& link : links) {
    keep_connected(*link, now);
    auto snapshot = hub.sensor(link->config.name);
    if (!snapshot) continue;
    const bool republish = std::exchange(link->republish, false);
    // What waited goes first: after a reconnect without its stale retained messages; otherwise
    // what a publish refused in passing (a connection that dropped and came back in between).
    if (republish || link->connected) link->flush(republish);
    const bool online = snapshot->health.connected;
    nlohmann::json status = hub::sensor_json(*snapshot);
    nlohmann::json without_health = status;
    without_health.erase("health");
    without_health.erase("last_id");
    std::string fingerprint = without_health.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    const bool changed = fingerprint != link->last_status;
    link->last_status = std::move(fingerprint);
    const bool status_now = link->status_now.exchange(false) || changed;
    if (republish || status_now || link->online != online || now >= link->next_status) {
      if (republish && config.discovery) {
        for (Message& message : discovery_messages(*link, config)) link->send(std::move(message));
      }
      if (republish || link->online != online) {
        link->send(Message{link->topic + "/availability", online ? "online" : "offline", config.qos_state, true});
      }
      status["service"] = config.client_id;
      link->send(Message{link->topic + "/status", status.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                         config.qos_state, true});
      link->online = online;
      link->next_status = now + options.status_interval;
    }
  }
}

// The clean stop's waits: the sockets are served while `pending()` holds, for at most `limit`.
template <class Pending>
void Bridge::Impl::serve_while(Pending pending, std::chrono::milliseconds limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (pending() && std::chrono::steady_clock::now() < until) serve_sockets(50ms);
}

// A clean stop says offline itself (the broker sends no will after a DISCONNECT) and
// waits, bounded, for the broker to acknowledge it, then disconnects every session.
void Bridge::Impl::say_offline_and_disconnect() {
  // The fast path's last readings first, bounded. A session whose socket never takes the rest
  // of a packet writes nothing more: closed without DISCONNECT, its will says offline.
  const auto unsent = [&] {
    return std::any_of(links.begin(), links.end(),
                       [](const auto& link) { return link->connected && !link->out.empty(); });
  };
  for (const auto& link : links) link->write_out();
  serve_while(unsent, 1s);
  const int qos = std::max(options.config.qos_state, 1);
  for (const auto& link : links) {
    int mid = -1;
    if (link->connected && !link->out.mid_packet() &&
        link->try_publish(Message{link->topic + "/availability", "offline", qos, true}, &mid) == Link::Publish::sent) {
      link->offline_mid = mid;
    }
  }
  const auto waiting = [&] {
    return std::any_of(links.begin(), links.end(), [](const auto& link) {
      return link->connected && link->offline_mid >= 0 && !link->offline_acked;
    });
  };
  serve_while(waiting, 5s);
  for (const auto& link : links) {
    if (mosquitto_socket(link->client) >= 0 && !link->out.mid_packet()) {
      mosquitto_disconnect(link->client);
      link->disconnect_sent = true;
    }
  }
  // The DISCONNECTs that did not fit the sockets at once.
  const auto open = [&] {
    return std::any_of(links.begin(), links.end(),
                       [](const auto& link) { return link->disconnect_sent && mosquitto_socket(link->client) >= 0; });
  };
  serve_while(open, 1s);
  // What the broker never took (a session that would not drain) is lost with the socket: counted.
  for (const auto& link : links) link->drop_out();
}

void Bridge::Impl::run_network() {
  auto subscription = hub.subscribe("", 65536, hub::OverflowPolicy::drop_oldest);
  if (!subscription) log("mqtt: cannot subscribe to the hub: " + subscription.error().message);
  if (subscription) (*subscription)->set_listener([waker = waker] { waker->signal(); });
  for (const auto& link : links) {
    // Refused or unreachable now is retried with backoff by keep_connected.
    mosquitto_connect_async(link->client, address.host.c_str(), address.port, options.keepalive_s);
  }
  using Clock = std::chrono::steady_clock;
  auto next_poll = Clock::now();
  // Hub items are taken at most once per drain_gather: woken by the first item of a quiet
  // spell the thread lets the next ones join it, so a drain carries several readings per
  // session and their send() (docs/mqtt.md, "The reading fast path"). While items flow it
  // drains on that timer alone, deaf to the hub's wake-ups (one wake-up per drain, not two);
  // a drain that finds nothing goes back to waiting for the hub, so an idle bridge sleeps.
  bool items_waiting = false;
  bool ticking = false;
  auto last_drain = Clock::now() - options.drain_gather;
  while (!closing) {
    auto now = Clock::now();
    // Wakes for hub items, replies, sockets, and at least every 20 ms for the windows' deadlines.
    auto wait = std::min<Clock::duration>(next_poll - now, 20ms);
    if (items_waiting || ticking) wait = std::min<Clock::duration>(wait, last_drain + options.drain_gather - now);
    const auto timeout = std::chrono::duration_cast<std::chrono::microseconds>(std::max<Clock::duration>(wait, 0us));
    if (serve_sockets(timeout, !ticking)) items_waiting = true;
    now = Clock::now();
    if (subscription && (items_waiting || ticking) && now >= last_drain + options.drain_gather) {
      items_waiting = false;
      last_drain = now;
      ticking = take_items(**subscription) > 0;
    }
    send_replies();
    now = std::chrono::steady_clock::now();
    for (const auto& link : links) {
      if (auto message = link->window.flush_due(now))
        link->send_reading(std::move(*message), options.config.qos_reading);
      link->write_out();  // the drain's fast-path readings, in one send() per session
    }
    if (now < next_poll) continue;
    next_poll = now + 100ms;
    poll_sensors(now);
  }
  if (subscription) (*subscription)->close();
  send_replies();
  say_offline_and_disconnect();
}

void Bridge::Impl::run_commands() {
  while (true) {
    Command command;
    {
      std::unique_lock lock(command_mutex);
      command_ready.wait(lock, [&] { return stopping || !commands.empty(); });
      if (commands.empty()) return;
      command = std::move(commands.front());
      commands.pop_front();
    }
    handle(command);
  }
}

void Bridge::Impl::handle(Command& command) {
  nlohmann::json result;
  try {
    result = result_of(command);
  } catch (const std::exception& e) {
    // Nothing leaves the command thread: a command that fails this way is answered, and the next one runs.
    result = hub::error_object("internal", std::string("the command could not be run: ") + e.what());
  }
  ++handled;
  answer(command, std::move(result));
}

void Bridge::Impl::answer(Command& command, nlohmann::json result) {
  Link& link = *command.link;
  if (result.contains("error")) result["ok"] = false;
  {
    const std::lock_guard lock(reply_mutex);
    replies.push_back(Reply{&link, link.topic + (command.is_set ? "/set/result" : "/action/result"),
                            result.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                            std::move(command.response_topic), std::move(command.correlation)});
  }
  link.status_now = true;  // settings may have changed: the status goes out again at once
  wake();
}

nlohmann::json Bridge::Impl::result_of(const Command& command) {
  if (command.refusal)
    return hub::error_object(command.refusal->code, command.refusal->message, command.refusal->field);
  return answer_command(hub, command.link->config.name, command.is_set ? CommandKind::set : CommandKind::action,
                        command.payload);
}

// Sessions made by a start() that failed before their threads ran, or stopped ones.
Bridge::Impl::~Impl() {
  for (const auto& link : links) {
    if (link->client != nullptr) mosquitto_destroy(link->client);
  }
}

Bridge::Bridge(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Bridge::~Bridge() { stop(); }

Result<std::unique_ptr<Bridge>> Bridge::start(hub::Hub& hub, BridgeOptions options) {
  auto address = hub::parse_broker_url(options.config.broker);
  if (!address) return std::move(address).error();
  init_library();
  auto impl = std::make_unique<Impl>(hub, std::move(options));
  impl->address = *address;
  if (impl->waker->fd < 0) return make_error(Errc::io, "mqtt: cannot make an eventfd for the network thread");
  const hub::MqttConfig& config = impl->options.config;
  for (const hub::SensorSnapshot& sensor : hub.sensors()) {
    impl->links.push_back(std::make_unique<Link>(*impl, sensor.config));
    Link& link = *impl->links.back();
    impl->by_sensor.emplace(sensor.config.name, &link);
    const std::string client_id = config.client_id + "-" + sensor.config.name;
    link.client = mosquitto_new(client_id.c_str(), true, &link);
    if (link.client == nullptr) return make_error(Errc::io, "mqtt: cannot make a client (out of memory)");
    mosquitto_int_option(link.client, MOSQ_OPT_PROTOCOL_VERSION, MQTT_PROTOCOL_V5);
    // Each reading leaves at once: with Nagle on, a publish behind an unacknowledged one
    // waits for the broker's delayed ACK (40 ms on Linux).
    mosquitto_int_option(link.client, MOSQ_OPT_TCP_NODELAY, 1);
    mosquitto_connect_v5_callback_set(link.client, on_connect);
    mosquitto_disconnect_v5_callback_set(link.client, on_disconnect);
    mosquitto_publish_v5_callback_set(link.client, on_publish);
    mosquitto_subscribe_v5_callback_set(link.client, on_subscribe);
    mosquitto_message_v5_callback_set(link.client, on_message);
    // The fast path writes the socket itself: plain TCP only, and a topic libmosquitto would take.
    link.direct = !address->tls &&
                  mosquitto_validate_utf8(link.reading_topic.c_str(), static_cast<int>(link.reading_topic.size())) ==
                      MOSQ_ERR_SUCCESS &&
                  mosquitto_pub_topic_check2(link.reading_topic.c_str(), link.reading_topic.size()) == MOSQ_ERR_SUCCESS;
    const std::string availability = link.topic + "/availability";
    mosquitto_will_set_v5(link.client, availability.c_str(), 7, "offline", config.qos_state, true, nullptr);
    if (!config.username.empty()) {
      mosquitto_username_pw_set(link.client, config.username.c_str(),
                                config.password.empty() ? nullptr : config.password.c_str());
    }
    if (address->tls) {
      const int rc = mosquitto_tls_set(link.client, config.ca_file.empty() ? nullptr : config.ca_file.c_str(),
                                       config.ca_file.empty() ? "/etc/ssl/certs" : nullptr, nullptr, nullptr, nullptr);
      if (rc != MOSQ_ERR_SUCCESS) {
        return make_error(Errc::io, "mqtt: TLS with CA file '" + config.ca_file + "': " + mosquitto_strerror(rc));
      }
    }
  }
  Impl* raw = impl.get();
  impl->network = std::thread([raw] { raw->run_network(); });
  impl->commander = std::thread([raw] { raw->run_commands(); });
  return std::unique_ptr<Bridge>(new Bridge(std::move(impl)));
}

void Bridge::stop() {
  if (!impl_ || impl_->stopping.exchange(true)) return;
  impl_->command_ready.notify_all();
  if (impl_->commander.joinable()) impl_->commander.join();
  // After the commands, so that their results still go out before offline.
  impl_->closing = true;
  impl_->wake();
  if (impl_->network.joinable()) impl_->network.join();
  for (const auto& link : impl_->links) {
    mosquitto_destroy(link->client);
    link->client = nullptr;
  }
}

BridgeStats Bridge::stats() const {
  BridgeStats stats;
  stats.broker = impl_->options.config.broker;
  stats.connected = impl_->connected_links.load() == static_cast<int>(impl_->links.size());
  {
    const std::lock_guard lock(impl_->state_mutex);
    stats.error = impl_->error;
  }
  stats.dropped = impl_->hub_lost.load();
  stats.commands = impl_->handled.load();
  stats.busy = impl_->busy.load();
  stats.refusals = impl_->refusals.load();
  for (const auto& link : impl_->links) {
    stats.published += link->published.load();
    stats.dropped += link->dropped.load();
    stats.queued += link->queued.load();
    stats.reconnects += link->reconnects.load();
  }
  return stats;
}

}  // namespace rangekit::mqtt
