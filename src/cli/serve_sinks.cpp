#include "cli/serve_sinks.hpp"

#include <fmt/core.h>

#include <cstdio>

namespace rangekit::cli {

Result<SinkList> start_sinks(hub::Hub& hub, const hub::SiteConfig& site, const std::string& spool_dir) {
  SinkList started;
  for (const hub::SinkConfig& config : site.sinks) {
    sinks::SinkOptions options;
    options.config = config;
    options.spool_dir = spool_dir;
    options.log = [](const std::string& line) {
      fmt::print("{}\n", line);
      std::fflush(stdout);
    };
    auto sink = sinks::Sink::start(hub, options);
    if (!sink) return std::move(sink).error();
    const std::string sensors =
        config.sensors.empty() ? "every sensor" : fmt::format("{} sensors", config.sensors.size());
    fmt::print("rangekit serve: sink {} ({}): {}, spool {} (docs/sinks.md)\n", config.url, config.kind, sensors,
               (*sink)->spool_path());
    started.push_back(std::move(*sink));
  }
  return started;
}

std::string sink_check_line(const hub::SinkConfig& sink) {
  std::string sensors = "every sensor";
  if (!sink.sensors.empty()) {
    sensors.clear();
    for (const std::string& name : sink.sensors) sensors += (sensors.empty() ? "" : ", ") + name;
  }
  return fmt::format("sink {} ({}): {}, {}, spool up to {} MB, drain {} rows/s", sink.url, sink.kind, sensors,
                     sink.max_rate_hz > 0 ? fmt::format("at most {} readings/s per sensor", sink.max_rate_hz)
                                          : std::string("every reading"),
                     sink.spool_max_mb, sink.drain_rate);
}

std::string sink_summary(const sinks::SinkStats& stats) {
  return fmt::format("sink {}: written {}, spooled {}, dropped {}, rejected {}, spool {} B, {}", stats.url,
                     stats.written, stats.spooled, stats.dropped, stats.rejected, stats.spool_bytes,
                     stats.up ? "up" : "down" + (stats.error.empty() ? std::string() : " (" + stats.error + ")"));
}

}  // namespace rangekit::cli
