// A historian sink of the sensor hub (docs/sinks.md): every reading of its sensors, as Influx
// line protocol over HTTP or COPY rows into PostgreSQL, through a spool on disk that a reading
// leaves only once the historian confirmed it. It reaches the sensors only through hub::Hub.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "rangekit/core/result.hpp"
#include "rangekit/hub/hub.hpp"
#include "rangekit/hub/site_config.hpp"

namespace rangekit::sinks {

struct SinkOptions {
  hub::SinkConfig config;  // kind, url, sensors, max_rate_hz, spool_max_mb, drain_rate
  std::string spool_dir;   // the spool file goes here (spool_file_name), created if missing
  // Hub items go to the spool at most this often, each time in one transaction: at 2000
  // readings/s the sink took 3.3 % of a core at 20 ms, 2.3 % at 100 ms (WAL page writes).
  std::chrono::milliseconds intake_gather{100};
  std::size_t queue = 65536;                // hub items held between the hub and the spool; the oldest go first
  std::chrono::milliseconds timeout{5000};  // one HTTP exchange, at most
  // After a failed write the batch is retried after a wait doubling from min to max.
  std::chrono::milliseconds backoff_min{250};
  std::chrono::milliseconds backoff_max{5000};
  std::size_t batch_rows = 5000;                // rows per write, at most
  std::chrono::milliseconds batch_time{100};    // a write goes at least this often while rows wait
  std::function<void(const std::string&)> log;  // one line per event worth telling
};

struct SinkStats {
  std::string url;
  bool up = false;                // the last write was confirmed
  std::string error;              // why the last write failed, while down
  std::uint64_t written = 0;      // rows the historian confirmed, since the start
  std::uint64_t spooled = 0;      // rows waiting in the spool now
  std::uint64_t spool_bytes = 0;  // their size
  std::uint64_t dropped = 0;      // oldest spooled rows dropped past spool_max_mb, and items the hub
                                  // queue lost (drop_oldest), since the start
  std::uint64_t rejected = 0;     // rows the historian refused as malformed (HTTP 400): never retried
  std::uint64_t failures = 0;     // writes that failed and wait to be retried
  double oldest_age_s = 0;        // of the oldest spooled row; 0 when none waits
};

// "influx-127.0.0.1-8428-write.spool": the spool of a sink, from its kind and URL without its
// password (hub::redacted_url) and a postgres sink's table, so a restart with the same
// [[sink]] finds its rows again.
std::string spool_file_name(const hub::SinkConfig& config);

class Sink {
 public:
  // Opens the spool (rows of an earlier run are sent first) and starts the sink's two threads:
  // one takes the hub's readings into the spool, one sends the spool to the historian. A URL
  // that cannot work or a spool that cannot be opened is an error here; a historian that is
  // down is not (rows wait).
  static Result<std::unique_ptr<Sink>> start(hub::Hub& hub, SinkOptions options);
  ~Sink();  // stop()
  Sink(const Sink&) = delete;
  Sink& operator=(const Sink&) = delete;
  // Stops taking readings (those queued go to the spool) and sending. Idempotent.
  void stop();
  [[nodiscard]] SinkStats stats() const;
  [[nodiscard]] std::string spool_path() const;

  struct Impl;

 private:
  explicit Sink(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace rangekit::sinks
