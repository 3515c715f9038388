// The historian sinks of `rangekit serve` ([[sink]] tables, docs/sinks.md): started on the
// hub, a line for each at start and its counts at the end.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/hub/hub.hpp"
#include "rangekit/sinks/sink.hpp"

namespace rangekit::cli {

using SinkList = std::vector<std::unique_ptr<sinks::Sink>>;

// One sink per [[sink]], each spooling into `spool_dir`; the first that cannot start is the error.
Result<SinkList> start_sinks(hub::Hub& hub, const hub::SiteConfig& site, const std::string& spool_dir);
// "sink http://…/write (influx): every sensor, every reading, spool up to 1024 MB, drain 20000 rows/s".
std::string sink_check_line(const hub::SinkConfig& sink);
// "sink http://…/write: written 5000, spooled 0, dropped 0, spool 0 B, up".
std::string sink_summary(const sinks::SinkStats& stats);

}  // namespace rangekit::cli
