#include "web/access.hpp"

#include <charconv>

#include "rangekit/web/server.hpp"

namespace rangekit::web {

Access access_of(const Target& target, http::verb method) {
  const auto& path = target.segments;
  if (path.size() == 1 && path[0] == "healthz" && method == http::verb::get) return Access::health;
  const bool api = !path.empty() && (path[0] == "api" || path[0] == "metrics");
  if (!api && method == http::verb::get) return Access::page;
  if (method != http::verb::get) return Access::write;
  if (!path.empty() && path.back() == "events") return Access::stream;
  return Access::read;
}

bool is_loopback_host(const std::string& host) {
  if (host == "localhost") return true;
  std::string_view literal = host;
  if (literal.size() > 2 && literal.front() == '[' && literal.back() == ']')
    literal = literal.substr(1, literal.size() - 2);
  boost::system::error_code error;
  const auto address = net::ip::make_address(literal, error);
  // make_address takes "127.1" and "0x7f.1" too; only the dotted or colon form counts.
  return !error && address.is_loopback() && address.to_string() == literal;
}

bool host_names_service(std::string_view host, const tcp::endpoint& local, bool tls) {
  std::string_view name = host;
  std::uint16_t port = tls ? 443 : 80;
  const std::size_t bracket = host.rfind(']');
  const std::size_t colon = host.rfind(':');
  if (colon != std::string_view::npos && (bracket == std::string_view::npos || colon > bracket)) {
    name = host.substr(0, colon);
    const std::string_view digits = host.substr(colon + 1);
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), port);
    if (digits.empty() || error != std::errc{} || end != digits.data() + digits.size()) return false;
  }
  if (name.empty() || port != local.port()) return false;
  if (is_loopback_host(std::string(name))) return local.address().is_loopback() || local.address().is_unspecified();
  if (local.address().is_unspecified()) return true;
  return name == host_text(local.address());
}

std::string host_text(const net::ip::address& address) {
  return address.is_v6() ? "[" + address.to_string() + "]" : address.to_string();
}

bool same_secret(std::string_view given, std::string_view secret) {
  if (secret.empty()) return false;
  unsigned differ = given.size() == secret.size() ? 0 : 1;
  for (std::size_t i = 0; i < given.size(); ++i) {
    differ |= static_cast<unsigned char>(given[i]) ^ static_cast<unsigned char>(secret[i % secret.size()]);
  }
  return differ == 0;
}

}  // namespace rangekit::web
