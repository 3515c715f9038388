#include "rangekit/core/address_range.hpp"

#include <charconv>
#include <string>

namespace rangekit {
namespace {

std::optional<unsigned> number_of(std::string_view text, unsigned max) noexcept {
  unsigned value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || text.size() > 3 || error != std::errc{} || end != text.data() + text.size() || value > max) {
    return std::nullopt;
  }
  return value;
}

}  // namespace

std::optional<std::uint32_t> parse_ipv4(std::string_view text) noexcept {
  std::uint32_t address = 0;
  for (int part = 0; part < 4; ++part) {
    const auto dot = text.find('.');
    if ((part < 3) == (dot == std::string_view::npos)) return std::nullopt;
    const auto value = number_of(text.substr(0, dot), 255);
    if (!value) return std::nullopt;
    address = (address << 8) | *value;
    text = part < 3 ? text.substr(dot + 1) : std::string_view{};
  }
  return address;
}

Result<AddressRange> parse_address_range(std::string_view text) {
  const auto slash = text.find('/');
  const auto address = parse_ipv4(text.substr(0, slash));
  if (!address) {
    return make_error(Errc::out_of_range, "'" + std::string(text) + "' is not an IPv4 address or range (10.0.0.0/8)");
  }
  unsigned prefix = 32;
  if (slash != std::string_view::npos) {
    const auto value = number_of(text.substr(slash + 1), 32);
    if (!value) return make_error(Errc::out_of_range, "'" + std::string(text) + "': the prefix is not 0-32");
    prefix = *value;
  }
  const std::uint32_t mask = prefix == 0 ? 0 : ~std::uint32_t{0} << (32 - prefix);
  if ((*address & ~mask) != 0) {
    return make_error(Errc::out_of_range, "'" + std::string(text) + "' has host bits set: a /" +
                                              std::to_string(prefix) + " range starts at a multiple of its size");
  }
  return AddressRange{*address, mask};
}

}  // namespace rangekit
