// Bridge::Impl: the state the bridge's network thread, command thread and libmosquitto
// callbacks share, and the commands and replies that pass between those threads.
#pragma once

#include <mosquitto.h>

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "mqtt/wake_fd.hpp"
#include "rangekit/hub/hub.hpp"
#include "rangekit/hub/site_config.hpp"
#include "rangekit/mqtt/bridge.hpp"

namespace rangekit::mqtt {

struct Link;  // mqtt/sensor_link.hpp

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

// A command's result, published by the network thread.
struct Reply {
  Link* link = nullptr;
  std::string topic;
  std::string payload;
  std::string response_topic;  // MQTT 5
  std::string correlation;
};

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

  // The network thread (network_loop.cpp).
  void run_network();
  bool serve_sockets(std::chrono::microseconds timeout, bool hear_wake = true);
  template <class Pending>
  void serve_while(Pending pending, std::chrono::milliseconds limit);
  std::size_t take_items(hub::Subscription& subscription);
  void poll_sensors(std::chrono::steady_clock::time_point now);
  void keep_connected(Link& link, std::chrono::steady_clock::time_point now) const;
  void say_offline_and_disconnect();

  // Commands (commands.cpp).
  void subscribe_commands(Link& link);
  void receive_command(Link& link, const mosquitto_message& message, const mosquitto_property* props);
  void run_commands();
  void handle(Command& command);
  // Queues the command's answer for the network thread: on its result topic, and on its
  // response topic when it named one.
  void answer(Command& command, nlohmann::json result);
  nlohmann::json result_of(const Command& command);
  void send_replies();

  // A session's events, from libmosquitto's callbacks on the network thread (mosquitto_callbacks.cpp).
  void on_connected(Link& link, int reason);
  void on_subscribed(Link& link, int mid, int count, const int* granted);
  void on_lost(Link& link, int reason);
};

}  // namespace rangekit::mqtt
