// Whether a request may be answered, by the rules of web/access.hpp: its Host, a write's
// Origin and the token; a refusal is answered here (403 or 401).
#pragma once

#include "web/access.hpp"
#include "web/exchange.hpp"

namespace rangekit::web {

// False after answering why not. Runs before routing, so a refused client learns nothing
// of the paths or sensors.
bool admitted(Exchange& exchange, const Target& target, Access access);

// No token set (loopback only), or the right one: in the header, or in the query of a read.
bool has_token(const Exchange& exchange, const Target& target, Access access);

}  // namespace rangekit::web
