// The route table: method and path pattern to handler, for every path of the API
// (docs/api.md, docs/openapi.yaml), and what a request passes before it reaches one.
#include "web/routes.hpp"

#include <algorithm>
#include <array>
#include <string_view>
#include <vector>

#include "rangekit/core/text.hpp"
#include "web/auth.hpp"
#include "web/resources.hpp"

namespace rangekit::web {
namespace {

using Handler = void (*)(Exchange&, const Matched&);

struct Route {
  http::verb method;
  std::string_view pattern;  // "/api/sensors/{name}/settings": a {placeholder} matches any one segment
  Handler handler;
  std::string_view parameters = "";  // the query keys it reads, space-separated; `token` goes anywhere
};

// The first row whose method and pattern match answers. A path that matches only rows of
// other methods gets 405, Allow listing their methods in this order (the order clients saw).
// tests/web/api_docs_test.cpp checks every path of docs/openapi.yaml against this table.
constexpr std::array kRoutes{
    Route{http::verb::get, "/healthz", get_health},
    Route{http::verb::get, "/metrics", get_metrics},
    Route{http::verb::get, "/api/events", get_all_events, "after max_rate"},
    Route{http::verb::get, "/api/captures", list_captures},
    Route{http::verb::post, "/api/captures", start_capture},
    Route{http::verb::get, "/api/captures/{id}", get_capture},
    Route{http::verb::post, "/api/captures/{id}/stop", stop_capture},
    Route{http::verb::get, "/api/captures/{id}/download", download_capture, "format"},
    Route{http::verb::get, "/api/families", list_families},
    Route{http::verb::get, "/api/sinks", list_sinks},
    Route{http::verb::get, "/api/sensors", list_sensors},
    Route{http::verb::get, "/api/sensors/{name}", get_sensor},
    Route{http::verb::get, "/api/sensors/{name}/settings", get_settings},
    Route{http::verb::patch, "/api/sensors/{name}/settings", patch_settings},
    Route{http::verb::get, "/api/sensors/{name}/settings/schema", get_settings_schema},
    Route{http::verb::post, "/api/sensors/{name}/actions/{action}", post_action, "argument"},
    // Reading a whole configuration pauses an LS5 stream, so even the export is a POST.
    Route{http::verb::post, "/api/sensors/{name}/config", export_config},
    Route{http::verb::put, "/api/sensors/{name}/config", import_config},
    // Both talk to the bus (a scan holds the poll while it asks), so both are POSTs; any
    // other name there is a POST too, so that a GET of it says so.
    Route{http::verb::post, "/api/sensors/{name}/bus/scan", scan_bus},
    Route{http::verb::post, "/api/sensors/{name}/bus/assign", assign_address},
    Route{http::verb::post, "/api/sensors/{name}/bus/{call}", no_such_bus_call},
    Route{http::verb::get, "/api/sensors/{name}/samples", get_samples, "after limit"},
    Route{http::verb::get, "/api/sensors/{name}/events", get_sensor_events, "after max_rate"},
};

using Lookup = bool (*)(Exchange&, Matched&);

// Paths at and under these name something that must exist: without it they answer 404
// whatever the method or the rest of the path. Checked in this order, before the routes.
struct Scope {
  std::string_view pattern;
  Lookup lookup;  // false after answering
};

bool find_captures(Exchange& exchange, Matched& matched) {
  matched.captures = exchange.server().options.captures;
  if (matched.captures != nullptr) return true;
  exchange.not_found("this service keeps no captures");
  return false;
}

bool find_capture(Exchange& exchange, Matched& matched) {
  auto capture = matched.captures->info(matched.id);
  if (!capture) {
    exchange.not_found(capture.error().message);
    return false;
  }
  matched.capture = std::move(*capture);
  return true;
}

bool find_sensor(Exchange& exchange, Matched& matched) {
  auto sensor = exchange.server().hub.sensor(matched.name);
  if (!sensor) {
    exchange.not_found(sensor.error().message);
    return false;
  }
  matched.sensor = std::move(*sensor);
  return true;
}

constexpr std::array kScopes{
    Scope{"/api/captures", find_captures},
    Scope{"/api/captures/{id}", find_capture},
    Scope{"/api/sensors/{name}", find_sensor},
};

// Calls visit(i, segment) for the pattern's segments in order ("/api/{name}": "api", "{name}")
// until it returns false; the number of segments visited.
template <class Visit>
std::size_t each_segment(std::string_view pattern, Visit visit) {
  std::size_t i = 0;
  for (std::size_t at = 1; at <= pattern.size(); ++i) {
    const std::size_t slash = std::min(pattern.find('/', at), pattern.size());
    if (!visit(i, pattern.substr(at, slash - at))) return i;
    at = slash + 1;
  }
  return i;
}

// The pattern's segments against the path's: all of them (whole), or the pattern's first.
bool matches(std::string_view pattern, const std::vector<std::string>& path, bool whole) {
  bool same = true;
  const std::size_t count = each_segment(pattern, [&](std::size_t i, std::string_view segment) {
    same = i < path.size() && (segment.front() == '{' || segment == path[i]);
    return same;
  });
  return same && (!whole || count == path.size());
}

// The path's segments under the pattern's {name}, {id} and {action}.
void bind(std::string_view pattern, const std::vector<std::string>& path, Matched& matched) {
  each_segment(pattern, [&](std::size_t i, std::string_view segment) {
    if (segment == "{name}") matched.name = path[i];
    if (segment == "{id}") matched.id = path[i];
    if (segment == "{action}") matched.action = path[i];
    return true;
  });
}

// A query key the route does not read is refused rather than ignored: `?limt=5` would
// otherwise quietly answer with the default limit. False after answering.
bool known_parameters(Exchange& exchange, const Route& row, const Target& target) {
  std::vector<std::string> known{"token"};
  for (std::size_t at = 0; at < row.parameters.size();) {
    const std::size_t space = std::min(row.parameters.find(' ', at), row.parameters.size());
    known.emplace_back(row.parameters.substr(at, space - at));
    at = space + 1;
  }
  for (const auto& [key, value] : target.query) {
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    std::string message = "'" + key + "' is no query parameter of " + std::string(http::to_string(row.method)) + " " +
                          std::string(row.pattern);
    if (const auto meant = text::closest(key, known)) message += "; did you mean '" + *meant + "'?";
    std::string takes;
    for (std::size_t i = 1; i < known.size(); ++i) takes += (i == 1 ? "" : ", ") + known[i];
    message += takes.empty() ? " (it takes none)" : " (it takes " + takes + ")";
    exchange.respond(http::status::bad_request, error_json("unknown_parameter", message, key));
    return false;
  }
  return true;
}

}  // namespace

void route(Exchange& exchange) {
  Matched matched;
  matched.target = parse_target(exchange.request().target());
  const auto& path = matched.target.segments;
  const auto method = exchange.request().method();
  if (!matched.target.valid) {
    return exchange.respond(http::status::bad_request, error_json("bad_target", "the path or query does not decode"));
  }
  if (!admitted(exchange, matched.target, access_of(matched.target, method))) return;
  for (const Scope& scope : kScopes) {
    if (!matches(scope.pattern, path, false)) continue;
    bind(scope.pattern, path, matched);
    if (!scope.lookup(exchange, matched)) return;
  }
  std::vector<http::verb> allowed;
  std::string allow;
  for (const Route& row : kRoutes) {
    if (!matches(row.pattern, path, true)) continue;
    if (row.method == method) {
      if (!known_parameters(exchange, row, matched.target)) return;
      bind(row.pattern, path, matched);
      return row.handler(exchange, matched);
    }
    if (std::find(allowed.begin(), allowed.end(), row.method) != allowed.end()) continue;
    allowed.push_back(row.method);
    allow += (allow.empty() ? "" : ", ") + std::string(http::to_string(row.method));
  }
  if (!allow.empty()) return exchange.wrong_method(allow);
  if (path.empty() || path[0] != "api") return get_static_file(exchange, matched);
  exchange.not_found("no such path (see docs/api.md)");
}

}  // namespace rangekit::web
