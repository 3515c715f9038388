// The historian sinks of `rangekit serve` ([[sink]] tables and --sink, docs/sinks.md): started
// on the hub, a line for each at start, their state for the HTTP face, their counts at the end.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/hub/hub.hpp"
#include "rangekit/sinks/sink.hpp"
#include "rangekit/web/server.hpp"

namespace rangekit::cli {

struct StartedSink {
  hub::SinkConfig config;
  std::unique_ptr<sinks::Sink> sink;
};
using SinkList = std::vector<StartedSink>;

// The site's [[sink]] tables and the --sink URLs (parse_sink_option) as one list; a --sink
// that is not a URL the sink of its kind takes, or that another sink already writes to (they
// would share one spool), is the error, for exit_bad_input.
Result<std::vector<hub::SinkConfig>> sink_configs(const hub::SiteConfig& site, const std::vector<std::string>& given);
// One sink per config, each spooling into `spool_dir`; the first that cannot start is the error.
Result<SinkList> start_sinks(hub::Hub& hub, const std::vector<hub::SinkConfig>& configs, const std::string& spool_dir);
// Each sink as /api/sinks, /metrics and /healthz show it, its URL without a password.
std::vector<web::SinkHealth> sinks_health(const SinkList& list);

// sinks_health as the HTTP face reads it: taken by the service's own loop, since a sink's
// stats wait for its spool's transaction (a WAL checkpoint's fsync on a slow card), which the
// event loop of every stream must not.
class SinksHealth {
 public:
  void refresh(const SinkList& list);
  [[nodiscard]] std::vector<web::SinkHealth> get() const;

 private:
  mutable std::mutex mutex_;
  std::vector<web::SinkHealth> health_;
};
// "sink http://…/write (influx): every sensor, every reading, spool up to 1024 MB, drain 20000 rows/s".
std::string sink_check_line(const hub::SinkConfig& sink);
// "sink http://…/write: written 5000, spooled 0, dropped 0, spool 0 B, up".
std::string sink_summary(const sinks::SinkStats& stats);

}  // namespace rangekit::cli
