// The service's own state: GET /healthz for anyone, GET /metrics for Prometheus.
#include "web/auth.hpp"
#include "web/metrics.hpp"
#include "web/resources.hpp"

namespace rangekit::web {

void get_health(Exchange& exchange, const Matched& matched) {
  Server::Impl& server = exchange.server();
  const auto faces = server.options.faces ? server.options.faces() : std::vector<FaceHealth>{};
  nlohmann::json health = health_json(server.hub, faces);
  // Without the token, which sensors and faces are down is not for everyone to read.
  if (!has_token(exchange, matched.target, Access::read)) health = nlohmann::json{{"status", health["status"]}};
  exchange.respond(http::status::ok, health.dump());
}

void get_metrics(Exchange& exchange, const Matched& /*matched*/) {
  const Server::Impl& server = exchange.server();
  const ServerStats stats{server.connections.load(), server.streams.open.load(), server.requests.load(),
                          server.refused.load(), server.streams.cut_off.load()};
  exchange.respond(http::status::ok, prometheus_text(server.hub, stats), true, "text/plain; version=0.0.4");
}

}  // namespace rangekit::web
