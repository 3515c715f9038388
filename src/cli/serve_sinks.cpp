#include "cli/serve_sinks.hpp"

#include <fmt/core.h>

#include <cstdio>

#include "rangekit/hub/sink_url.hpp"

namespace rangekit::cli {

Result<std::vector<hub::SinkConfig>> sink_configs(const hub::SiteConfig& site, const std::vector<std::string>& given) {
  std::vector<hub::SinkConfig> configs = site.sinks;
  for (const std::string& url : given) {
    auto sink = hub::parse_sink_option(url);
    if (!sink) return std::move(sink).error();
    // Checked as a [[sink]] url is: the influx sink writes to an http:// URL.
    if (sink->kind == "influx") {
      if (auto checked = hub::parse_http_url(sink->url); !checked) {
        return make_error(Errc::invalid_frame, "--sink: " + hub::redacted_text(checked.error().message));
      }
    }
    for (const hub::SinkConfig& other : configs) {
      if (sinks::spool_file_name(other) == sinks::spool_file_name(*sink)) {
        return make_error(Errc::invalid_frame, "--sink '" + hub::redacted_url(url) + "': another sink writes to " +
                                                   hub::redacted_url(other.url) +
                                                   " already (they would share a spool)");
      }
    }
    configs.push_back(std::move(*sink));
  }
  return configs;
}

Result<SinkList> start_sinks(hub::Hub& hub, const std::vector<hub::SinkConfig>& configs, const std::string& spool_dir) {
  SinkList started;
  for (const hub::SinkConfig& config : configs) {
    sinks::SinkOptions options;
    options.config = config;
    options.spool_dir = spool_dir;
    // A sink's lines name its URL as given: printed without its password.
    options.log = [](const std::string& line) {
      fmt::print("{}\n", hub::redacted_text(line));
      std::fflush(stdout);
    };
    auto sink = sinks::Sink::start(hub, options);
    if (!sink) {
      Error error = std::move(sink).error();
      error.message = "sink " + hub::redacted_url(config.url) + ": " + hub::redacted_text(error.message);
      return error;
    }
    const std::string sensors =
        config.sensors.empty() ? "every sensor" : fmt::format("{} sensors", config.sensors.size());
    fmt::print("rangekit serve: sink {} ({}): {}, spool {} (docs/sinks.md)\n", hub::redacted_url(config.url),
               config.kind, sensors, (*sink)->spool_path());
    started.push_back({config, std::move(*sink)});
  }
  return started;
}

std::vector<web::SinkHealth> sinks_health(const SinkList& list) {
  std::vector<web::SinkHealth> health;
  for (const StartedSink& each : list) {
    const sinks::SinkStats stats = each.sink->stats();
    health.push_back({each.config.kind, hub::redacted_url(each.config.url), stats.up, hub::redacted_text(stats.error),
                      stats.written, stats.spooled, stats.spool_bytes, stats.dropped, stats.rejected, stats.failures,
                      stats.oldest_age_s});
  }
  return health;
}

void SinksHealth::refresh(const SinkList& list) {
  auto taken = sinks_health(list);
  const std::lock_guard lock(mutex_);
  health_ = std::move(taken);
}

std::vector<web::SinkHealth> SinksHealth::get() const {
  const std::lock_guard lock(mutex_);
  return health_;
}

std::string sink_check_line(const hub::SinkConfig& sink) {
  std::string sensors = "every sensor";
  if (!sink.sensors.empty()) {
    sensors.clear();
    for (const std::string& name : sink.sensors) sensors += (sensors.empty() ? "" : ", ") + name;
  }
  return fmt::format("sink {} ({}): {}, {}, spool up to {} MB, drain {} rows/s", hub::redacted_url(sink.url), sink.kind,
                     sensors,
                     sink.max_rate_hz > 0 ? fmt::format("at most {} readings/s per sensor", sink.max_rate_hz)
                                          : std::string("every reading"),
                     sink.spool_max_mb, sink.drain_rate);
}

std::string sink_summary(const sinks::SinkStats& stats) {
  return fmt::format(
      "sink {}: written {}, spooled {}, dropped {}, rejected {}, spool {} B, {}", hub::redacted_url(stats.url),
      stats.written, stats.spooled, stats.dropped, stats.rejected, stats.spool_bytes,
      stats.up ? "up" : "down" + (stats.error.empty() ? std::string() : " (" + hub::redacted_text(stats.error) + ")"));
}

}  // namespace rangekit::cli
