// The HTTP API's paths (web/routes.cpp): what a handler gets of the request it was
// routed, and the entry point a connection calls for each request it reads.
#pragma once

#include <optional>
#include <string>

#include "web/exchange.hpp"

namespace rangekit::web {

// A request the route table matched: its target, the names its path holds, and the sensor
// or capture they name, looked up once before routing.
struct Matched {
  Target target;
  std::string name;                           // {name}: a sensor
  std::string id;                             // {id}: a capture
  std::string action;                         // {action}
  std::optional<hub::SensorSnapshot> sensor;  // the one {name} names
  hub::CaptureManager* captures = nullptr;    // under /api/captures: the service's (never null there)
  std::optional<hub::CaptureInfo> capture;    // the one {id} names
};

// Checks the target and who may ask (web/auth.hpp), then answers by the route table.
void route(Exchange& exchange);

}  // namespace rangekit::web
