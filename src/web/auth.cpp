// Admits a request or answers why not: Host, then a write's Origin, then the token.
#include "web/auth.hpp"

namespace rangekit::web {

// A Host naming this service (a name that resolved to 127.0.0.1 by DNS rebinding does not),
// for a write no other Origin, then the token.
bool admitted(Exchange& exchange, const Target& target, Access access) {
  if (access == Access::page || access == Access::health) return true;
  const Request& request = exchange.request();
  Server::Impl& server = exchange.server();
  const std::string host(request[http::field::host]);
  if (!host_names_service(host, server.local, server.tls.has_value())) {
    exchange.respond(
        http::status::forbidden,
        error_json("bad_host", "Host '" + host + "' does not name this service (" + server.local_text + ")"));
    return false;
  }
  const std::string origin(request[http::field::origin]);
  const std::string_view scheme = exchange.tls() ? "https" : "http";
  if (access == Access::write && !origin.empty() && origin != std::string(scheme) + "://" + host) {
    exchange.respond(http::status::forbidden,
                     error_json("bad_origin", "Origin '" + origin + "' may not write to this service"));
    return false;
  }
  if (has_token(exchange, target, access)) return true;
  const bool in_address = access == Access::write && target.query.count("token") != 0;
  exchange.respond(http::status::unauthorized,
                   error_json("unauthorized", in_address ? "a write takes the token in Authorization: Bearer TOKEN, "
                                                           "not in the address (?token= is for streams and links)"
                                                         : "this service listens beyond loopback: send Authorization: "
                                                           "Bearer TOKEN (printed at its first start, kept in its "
                                                           "token file), or ?token= on a stream or link"));
  return false;
}

bool has_token(const Exchange& exchange, const Target& target, Access access) {
  const std::string& token = exchange.server().options.token;
  if (token.empty()) return true;
  const std::string_view header = exchange.request()[http::field::authorization];
  if (header.rfind("Bearer ", 0) == 0 && same_secret(header.substr(7), token)) return true;
  const auto query = target.query.find("token");
  return access != Access::write && query != target.query.end() && same_secret(query->second, token);
}

}  // namespace rangekit::web
