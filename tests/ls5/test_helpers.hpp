// Small helpers for the LS5 tests: bytes from literals, wire text of a frame.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string_view>
#include <vector>

#include "rangekit/core/framer.hpp"

namespace ls5_test {

// Byte lists for range-for loops without narrowing warnings.
using U8s = std::initializer_list<std::uint8_t>;

inline rangekit::Bytes bytes_of(std::string_view text) { return rangekit::as_bytes(text); }

inline std::vector<std::uint8_t> hex_bytes(std::initializer_list<int> values) {
  std::vector<std::uint8_t> out;
  for (const int v : values) out.push_back(static_cast<std::uint8_t>(v));
  return out;
}

template <class Text>
std::vector<std::uint8_t> wire(const Text& frame) {
  const auto bytes = frame.bytes();
  return {bytes.begin(), bytes.end()};
}

}  // namespace ls5_test
