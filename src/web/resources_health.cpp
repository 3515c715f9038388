// The service's own state: GET /healthz for anyone, GET /metrics for Prometheus, GET
// /api/sinks for the historians.
#include "web/auth.hpp"
#include "web/metrics.hpp"
#include "web/resources.hpp"
#include "web/sink_views.hpp"

namespace rangekit::web {
namespace {

std::vector<SinkHealth> sinks_of(const Server::Impl& server) {
  return server.options.sinks ? server.options.sinks() : std::vector<SinkHealth>{};
}

// A URL or an error message is text the service was given or met: not always UTF-8.
std::string json_text(const nlohmann::json& json) {
  return json.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace

void get_health(Exchange& exchange, const Matched& matched) {
  Server::Impl& server = exchange.server();
  const auto faces = server.options.faces ? server.options.faces() : std::vector<FaceHealth>{};
  nlohmann::json health = health_json(server.hub, faces, sinks_of(server));
  // Without the token, which sensors and faces are down is not for everyone to read.
  if (!has_token(exchange, matched.target, Access::read)) health = nlohmann::json{{"status", health["status"]}};
  exchange.respond(http::status::ok, json_text(health));
}

void get_metrics(Exchange& exchange, const Matched& /*matched*/) {
  const Server::Impl& server = exchange.server();
  const ServerStats stats{server.connections.load(), server.streams.open.load(), server.requests.load(),
                          server.refused.load(), server.streams.cut_off.load()};
  exchange.respond(http::status::ok, prometheus_text(server.hub, stats, sinks_of(server)), true,
                   "text/plain; version=0.0.4");
}

void list_sinks(Exchange& exchange, const Matched& /*matched*/) {
  nlohmann::json listed = nlohmann::json::array();
  for (const SinkHealth& sink : sinks_of(exchange.server())) listed.push_back(sink_json(sink));
  exchange.respond(http::status::ok, json_text(listed));
}

}  // namespace rangekit::web
