// Strict, allocation-free parsing of the numeric fields both protocols use.
// Each parser accepts exactly the documented form and nothing else: no
// whitespace, no exponent, no "inf"; std::nullopt means "not that form".
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace rangekit::text {

// Unsigned decimal integer, 1..max_digits digits, value <= max_value.
std::optional<std::uint64_t> parse_unsigned(std::string_view digits, std::size_t max_digits = 19,
                                            std::uint64_t max_value = UINT64_MAX) noexcept;

// Hexadecimal, 1..max_digits digits, upper or lower case.
std::optional<std::uint64_t> parse_hex(std::string_view digits, std::size_t max_digits = 16) noexcept;

// Fixed-point decimal "[-]digits[<sep>digits]" with the given separator ('.' for
// ULS, ',' for the LS5 identification). At most 15 significant digits.
std::optional<double> parse_decimal(std::string_view field, char separator = '.') noexcept;

// Splits `text` at `separator` into at most out.size() fields; returns the count,
// or out.size() + 1 when there are more fields than room.
std::size_t split(std::string_view text, char separator, std::span<std::string_view> out) noexcept;

// Writes `value` as exactly `width` upper-case hex digits into out (size >= width).
void write_hex(std::uint64_t value, std::size_t width, char* out) noexcept;

// A byte as two upper-case hex digits: 0x0B -> "0B". Every message that names an
// address or a byte in hex is written with it.
std::string hex_byte(std::uint8_t value);

// `text` safe to print in a message: control characters (NUL, ESC, DEL, ...) as \xNN,
// and with `ascii_only` every byte outside printable ASCII too (text that may not be
// UTF-8). At most `limit` bytes of `text` are shown, then "...".
std::string printable(std::string_view text, bool ascii_only = false, std::size_t limit = 200);

// The candidate a typo most likely meant ("moed" -> "mode", "binnig" -> "binning"): the closest
// by edit distance (a swap of two neighbours counts one), if it is within a third of the
// word's length, at least 1, and no other candidate is as close; nothing otherwise.
std::optional<std::string> closest(std::string_view typed, std::span<const std::string> candidates);

// Appends printf-formatted text (at most 511 bytes of it).
[[gnu::format(printf, 2, 3)]] void append_printf(std::string& out, const char* format, ...);

// Upper-case ASCII letters in place of lower-case ones.
inline char to_upper(char c) noexcept { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c; }

constexpr bool is_letter(char c) noexcept { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
constexpr bool is_digit(char c) noexcept { return c >= '0' && c <= '9'; }
constexpr bool is_hex_digit(char c) noexcept { return is_digit(c) || (c >= 'A' && c <= 'F') || (c >= 'a' && c <= 'f'); }

}  // namespace rangekit::text
