// Helpers for error messages (failure path only: these allocate).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "rangekit/core/result.hpp"
#include "rangekit/core/text.hpp"

namespace rangekit::ls5::detail {

// 'text' with control and non-ASCII bytes as \xNN, so messages stay printable.
// Text longer than max_quoted_bytes is cut there: "'...'... (4096 bytes)".
inline constexpr std::size_t max_quoted_bytes = 96;
std::string quote(std::string_view text);

// Error whose message starts with "LS5 frame: ".
Error frame_error(Errc code, std::string message);

}  // namespace rangekit::ls5::detail
