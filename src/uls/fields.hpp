// Small helpers shared by the ULS sources: field syntax, number writing, and
// the wording of error messages. Internal (src/), not part of the public API.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "rangekit/uls/frame.hpp"

namespace rangekit::uls::detail {

// What parse_common_frame reads: offsets into the frame, not views, so that no
// 128 bytes of string_views are zeroed per line. Field i runs from
// starts[i] to the comma (or end) before starts[i + 1].
struct CommonFrame {
  Address address;
  std::string_view text;
  std::size_t mnemonic_at = 0;
  std::size_t mnemonic_size = 0;
  std::size_t count = 0;
  // Left uninitialised on purpose (that is the point); written before read.
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-member-init)
  std::array<std::uint8_t, max_fields + 1> starts;

  [[nodiscard]] std::string_view mnemonic() const noexcept { return {text.data() + mnemonic_at, mnemonic_size}; }
  [[nodiscard]] std::size_t size() const noexcept { return count; }
  [[nodiscard]] std::string_view operator[](std::size_t i) const noexcept {
    return {text.data() + starts[i], static_cast<std::size_t>(starts[i + 1] - 1 - starts[i])};
  }
};

// The frames units send most ("$BM,f1,...", "#aER,n"): start byte, unit address,
// a 2-4 letter mnemonic and 1-8 non-empty fields of plain bytes, read in one pass.
// False for anything else, which parse_frame's full checks then read or reject
// with a message: true only for frames they accept as the same view.
bool parse_common_frame(std::string_view frame, CommonFrame& out) noexcept;

bool equal_ignoring_case(std::string_view a, std::string_view b) noexcept;

// An integer field: optional '-', then decimal digits only. Large magnitudes
// saturate, so "99999999999999999999" still reads as a (too large) number.
struct IntegerField {
  bool is_number = false;
  bool negative = false;
  std::uint64_t magnitude = 0;
  // True when the field is a number in [min, max].
  [[nodiscard]] bool within(std::int64_t min, std::int64_t max) const noexcept;
};
IntegerField read_integer(std::string_view field) noexcept;

// Writes decimal digits of `value` at `out`; returns the count (at most 20).
std::size_t write_unsigned(std::uint64_t value, char* out) noexcept;
// Writes `scaled / 10^decimals` with exactly `decimals` digits after '.'.
std::size_t write_fixed(std::int64_t scaled, int decimals, char* out) noexcept;

// "0x2F": one byte for messages.
std::string hex_byte(std::uint8_t byte);
// The field quoted for messages, non-printable bytes as \xNN.
// Text longer than max_quoted_bytes is cut there: "'...'... (4096 bytes)".
inline constexpr std::size_t max_quoted_bytes = 96;
std::string quoted(std::string_view text);

}  // namespace rangekit::uls::detail
