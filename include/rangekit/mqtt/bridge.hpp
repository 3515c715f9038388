// The MQTT face of the sensor hub (docs/mqtt.md): every sensor of a site on the broker.
// It reaches the sensors only through hub::Hub, over a bounded subscription and bounded
// queues that drop and count their oldest entries, so a broker outage never blocks a sensor.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "rangekit/core/result.hpp"
#include "rangekit/hub/hub.hpp"
#include "rangekit/hub/site_config.hpp"

namespace rangekit::mqtt {

struct BridgeOptions {
  hub::MqttConfig config;                           // config.broker must be set
  std::chrono::milliseconds status_interval{5000};  // retained status refreshed this often (health counters)
  int reconnect_min_s = 1;                          // reconnect backoff: doubles from min to max
  int reconnect_max_s = 30;
  int keepalive_s = 30;
  // Hub items are taken at most this often: a drain then carries several readings per
  // sensor, written in one send() (docs/mqtt.md), for at most this much added latency.
  std::chrono::microseconds drain_gather{3000};
  // Commands waiting to run, at most: one more is answered `busy` at once and not run.
  std::size_t max_queued_commands = 64;
  // [mqtt] spool: each sensor's spool file goes here (created if missing).
  std::string spool_dir;
  // One line per event worth telling (connected, lost, refused credentials); the service prints them.
  std::function<void(const std::string&)> log;
};

struct BridgeStats {
  bool connected = false;       // every sensor's session is connected, its set and action subscribed (SUBACK)
  std::string error;            // a refusal that retrying will not fix (credentials), until a connect succeeds
  std::string broker;           // as configured
  std::uint64_t published = 0;  // messages handed to the broker's connection
  std::uint64_t dropped = 0;    // dropped from full queues, cut off by a lost connection, or fallen behind on
  std::uint64_t queued = 0;     // messages waiting for the broker now, in memory
  std::uint64_t spooled = 0;    // readings waiting on disk for the broker's acknowledgement ([mqtt] spool)
  std::uint64_t spool_bytes = 0;
  std::uint64_t reconnects = 0;  // sessions that came back after a loss
  std::uint64_t commands = 0;    // set/action requests handled
  std::uint64_t busy = 0;        // set/action requests answered `busy`: max_queued_commands were waiting
  std::uint64_t refusals = 0;    // connection attempts the broker refused (CONNACK with a reason)
};

class Bridge {
 public:
  // Starts one broker session per sensor (each with its will on the sensor's availability
  // topic) and the thread that publishes. A broker that is down is retried with backoff;
  // only a URL or TLS file that cannot work is an error here.
  static Result<std::unique_ptr<Bridge>> start(hub::Hub& hub, BridgeOptions options);
  ~Bridge();  // stop()
  Bridge(const Bridge&) = delete;
  Bridge& operator=(const Bridge&) = delete;
  // Marks every sensor offline (retained), then disconnects cleanly. Idempotent.
  void stop();
  [[nodiscard]] BridgeStats stats() const;

  struct Impl;

 private:
  explicit Bridge(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace rangekit::mqtt
