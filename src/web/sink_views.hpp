// The historian sinks as the API shows them: GET /api/sinks, their lines of GET /metrics and
// their part of GET /healthz. The service describes them (ServerOptions::sinks).
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "rangekit/web/server.hpp"

namespace rangekit::web {

// {"kind", "url", "up", "error", "written", "spooled", "spool_bytes", "dropped", "rejected",
// "failures", "oldest_age_s"}.
nlohmann::json sink_json(const SinkHealth& sink);
// A sink whose last write failed: /healthz says "degraded". One that has not written yet is
// not down (a site whose sensors are all quiet never writes).
bool sink_down(const SinkHealth& sink);
// The rangekit_sink_* families of /metrics, each sink labelled with its kind and URL.
void append_sink_metrics(std::string& out, const std::vector<SinkHealth>& sinks);

}  // namespace rangekit::web
