#include "rangekit/hub/sink_url.hpp"

#include <algorithm>
#include <array>
#include <cctype>

namespace rangekit::hub {

namespace {

bool same_letters(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

// Query keys whose value is a secret: libpq's password, InfluxDB 1.x's p, a token.
bool secret_key(std::string_view key) {
  constexpr std::array<std::string_view, 3> keys{"password", "p", "token"};
  return std::any_of(keys.begin(), keys.end(), [&](std::string_view each) { return same_letters(key, each); });
}

}  // namespace

std::string redacted_url(std::string_view url) {
  std::string out(url);
  const auto scheme = out.find("://");
  std::size_t query_from = scheme == std::string::npos ? 0 : scheme + 3;
  if (scheme != std::string::npos) {
    const auto at = out.rfind('@');
    const auto colon = out.find(':', scheme + 3);
    if (at != std::string::npos && at > scheme + 3 && colon < at) {
      out.replace(colon + 1, at - colon - 1, "***");
      query_from = colon + 4;
    }
  }
  const auto query = out.find('?', query_from);
  if (query == std::string::npos) return out;
  // Each key=value to the next '&' (a '#' in a password would otherwise end it early).
  for (std::size_t at = query + 1; at < out.size();) {
    const std::size_t end = std::min(out.find('&', at), out.size());
    const std::size_t equals = out.find('=', at);
    if (equals < end && secret_key(std::string_view(out).substr(at, equals - at))) {
      out.replace(equals + 1, end - equals - 1, "***");
      at = equals + 5;
    } else {
      at = end + 1;
    }
  }
  return out;
}

std::string redacted_text(std::string_view text) {
  std::string out;
  for (std::size_t at = 0; at < text.size();) {
    const auto space = std::find_if(text.begin() + static_cast<std::ptrdiff_t>(at), text.end(),
                                    [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; });
    const std::size_t end = static_cast<std::size_t>(space - text.begin());
    std::string_view word = text.substr(at, end - at);
    if (word.find("://") == std::string_view::npos) {
      out += word;
    } else {
      const std::size_t kept = word.find_last_not_of(":,;.)'\"");
      const std::string_view after = word.substr(kept == std::string_view::npos ? 0 : kept + 1);
      word.remove_suffix(after.size());
      out += redacted_url(word);
      out += after;
    }
    if (end < text.size()) out += text[end];
    at = end + 1;
  }
  return out;
}

Result<SinkConfig> parse_sink_option(std::string_view url) {
  const auto scheme_is = [&](std::string_view scheme) {
    return url.size() >= scheme.size() && same_letters(url.substr(0, scheme.size()), scheme);
  };
  SinkConfig sink;
  if (scheme_is("postgresql://") || scheme_is("postgres://")) {
    sink.kind = "postgres";
    sink.url = std::string(url);
  } else if (scheme_is("influx+http://")) {
    sink.kind = "influx";
    sink.url = "http://" + std::string(url.substr(14));
  } else if (scheme_is("influx+https://")) {
    sink.kind = "influx";
    sink.url = "https://" + std::string(url.substr(15));
  } else {
    return make_error(Errc::invalid_frame,
                      "--sink '" + redacted_url(url) + "': give " + std::string(sink_option_forms));
  }
  return sink;
}

}  // namespace rangekit::hub
