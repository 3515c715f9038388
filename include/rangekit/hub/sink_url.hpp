// A sink's URL as the service shows it (start line, --check, summary, /api/sinks, /metrics,
// the sinks' own log lines and spool names: never a password) and as `rangekit serve --sink
// URL` gives one.
#pragma once

#include <string>
#include <string_view>

#include "rangekit/core/result.hpp"
#include "rangekit/hub/site_config.hpp"

namespace rangekit::hub {

// "postgresql://u:***@h/db": the password of the user part and the value of a query key that
// holds one (password=, p=, token=) replaced by ***; a URL without one as it is. The user part
// ends at the last '@', since a password may hold '/', '?' or '@' unescaped: more is hidden
// when the query holds an '@' too, never less.
std::string redacted_url(std::string_view url);

// A message with every URL in it (each word holding "://") as redacted_url shows it: what a
// sink logs or a refusal quotes. Punctuation after a URL ("URL: down", "'URL':") stays.
std::string redacted_text(std::string_view text);

// The forms --sink takes, for its refusal and its help.
inline constexpr std::string_view sink_option_forms =
    "postgresql://[USER[:PASSWORD]@]HOST[:PORT]/DB (or postgres://), influx+http://HOST[:PORT]/PATH or "
    "influx+https://HOST[:PORT]/PATH";

// `--sink URL` as a [[sink]] table of every sensor with the table's defaults: postgresql:// or
// postgres:// a sink of kind postgres with the URL as given, influx+http(s):// one of kind
// influx writing to the URL without "influx+". Anything else is refused, naming the forms.
Result<SinkConfig> parse_sink_option(std::string_view url);

}  // namespace rangekit::hub
