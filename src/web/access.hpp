// Who may do what over HTTP: every request is sorted into one kind of access before it is
// routed, so an unknown path or sensor learns nothing without the token. docs/security.md
// is this table in words; tests/web/access_test.cpp walks it against a running service.
#pragma once

#include <string>
#include <string_view>

#include "web/http.hpp"

namespace rangekit::web {

enum class Access {
  health,  // GET /healthz: anyone; without the token (when one is set) the status alone
  page,    // the dashboard's files: anyone, they hold no sensor data
  read,    // every other GET: Host, then the token (header, or ?token= for a link)
  stream,  // GET of an SSE stream: as a read (EventSource cannot send headers)
  write,   // PATCH, PUT, POST, anything else: Host, Origin, then the token in the header only
};

Access access_of(const Target& target, http::verb method);

// The Host header names this service: the port it listens on (443 or 80 when none is
// given), and a loopback literal or `localhost`, the address it is bound to, or any name
// when it is bound to every address (then the token guards it).
bool host_names_service(std::string_view host, const tcp::endpoint& local, bool tls);

// An address as a Host header names it: "127.0.0.1", "[::1]".
std::string host_text(const net::ip::address& address);

// Equal, in time that depends on the lengths only.
bool same_secret(std::string_view given, std::string_view secret);

}  // namespace rangekit::web
