// The dashboard's page and its files, embedded at build time (ServerOptions::assets), with
// the caching and browser-security headers docs/api.md lists.
#include <algorithm>
#include <string>

#include "web/resources.hpp"

namespace rangekit::web {

// Exact paths only (the page routes by #fragment).
void get_static_file(Exchange& exchange, const Matched& matched) {
  std::string path;
  for (const std::string& segment : matched.target.segments) path += "/" + segment;
  if (path.empty()) path.push_back('/');  // not = "/": g++ 12 warns of a false stringop-overflow there
  const auto& assets = exchange.server().options.assets;
  const auto found =
      std::find_if(assets.begin(), assets.end(), [&](const StaticAsset& asset) { return asset.path == path; });
  if (found == assets.end()) {
    return exchange.not_found(assets.empty() && path == "/"
                                  ? "this rangekit was built without the dashboard (-DRANGEKIT_DASHBOARD=OFF); the "
                                    "API is under /api (see docs/api.md)"
                                  : "no such path (see docs/api.md)");
  }
  const Request& request = exchange.request();
  if (request.method() != http::verb::get) return exchange.wrong_method("GET");
  const bool unchanged = !found->etag.empty() && request[http::field::if_none_match] == found->etag;
  auto response = std::make_shared<Response>(unchanged ? http::status::not_modified : http::status::ok,
                                             request.version() == 0 ? 11 : request.version());
  response->set(http::field::server, "rangekit");
  response->set(http::field::content_type, found->content_type);
  // Hashed names never change; the page itself is revalidated so a new build shows at once.
  response->set(http::field::cache_control, found->immutable ? "public, max-age=31536000, immutable" : "no-cache");
  if (!found->etag.empty()) response->set(http::field::etag, found->etag);
  response->set("X-Content-Type-Options", "nosniff");
  // Only this service's own scripts and API; no framing by another site (the pages write to sensors).
  response->set("Content-Security-Policy",
                "default-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data:; "
                "frame-ancestors 'none'; base-uri 'none'; form-action 'self'");
  response->set("Referrer-Policy", "no-referrer");
  response->keep_alive(request.keep_alive());
  if (!unchanged) response->body() = std::string(found->body);
  response->prepare_payload();
  exchange.send(std::move(response));
}

}  // namespace rangekit::web
