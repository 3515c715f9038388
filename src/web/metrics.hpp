// GET /metrics (Prometheus text format 0.0.4) and GET /healthz.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "rangekit/hub/hub.hpp"
#include "rangekit/web/server.hpp"

namespace rangekit::web {

std::string prometheus_text(const hub::Hub& hub, const ServerStats& server, const std::vector<SinkHealth>& sinks = {});
// {"status":"ok"|"degraded","sensors":N,"connected":M,"disconnected":[names]}: degraded
// while any sensor is disconnected, another face (MQTT) is not ok or a sink is down; each
// face under its name, the sinks (when there are any) under "sinks".
nlohmann::json health_json(const hub::Hub& hub, const std::vector<FaceHealth>& faces = {},
                           const std::vector<SinkHealth>& sinks = {});

}  // namespace rangekit::web
