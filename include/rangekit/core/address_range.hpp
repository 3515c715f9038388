// IPv4 addresses and ranges as a site file names who may connect: "10.0.0.7", "10.0.0.0/8".
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "rangekit/core/result.hpp"

namespace rangekit {

struct AddressRange {
  std::uint32_t network = 0;  // host byte order
  std::uint32_t mask = 0;
  [[nodiscard]] bool contains(std::uint32_t address) const noexcept { return (address & mask) == network; }
};

// Errc::out_of_range naming what is wrong: not dotted IPv4, a prefix beyond 32, host bits set.
Result<AddressRange> parse_address_range(std::string_view text);
// Dotted IPv4 in host byte order; none for anything else.
std::optional<std::uint32_t> parse_ipv4(std::string_view text) noexcept;

}  // namespace rangekit
