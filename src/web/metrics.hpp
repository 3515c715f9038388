// GET /metrics (Prometheus text format 0.0.4) and GET /healthz.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "rangekit/hub/hub.hpp"
#include "rangekit/web/server.hpp"

namespace rangekit::web {

std::string prometheus_text(const hub::Hub& hub, const ServerStats& server);
// {"status":"ok"|"degraded","sensors":N,"connected":M,"disconnected":[names]}: degraded
// while any sensor is disconnected or another face (MQTT) is not ok; each face under its name.
nlohmann::json health_json(const hub::Hub& hub, const std::vector<FaceHealth>& faces = {});

}  // namespace rangekit::web
