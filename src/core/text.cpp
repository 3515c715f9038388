#include "rangekit/core/text.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdarg>
#include <cstdio>
#include <vector>

namespace rangekit::text {

void append_printf(std::string& out, const char* format, ...) {
  std::array<char, 512> buffer{};
  va_list arguments;
  va_start(arguments, format);
  const int length = std::vsnprintf(buffer.data(), buffer.size(), format, arguments);
  va_end(arguments);
  if (length > 0) out.append(buffer.data(), std::min(static_cast<std::size_t>(length), buffer.size() - 1));
}

namespace {
int hex_value(char c) noexcept {
  if (is_digit(c)) return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return c - 'a' + 10;
}
}  // namespace

std::optional<std::uint64_t> parse_unsigned(std::string_view digits, std::size_t max_digits,
                                            std::uint64_t max_value) noexcept {
  if (digits.empty() || digits.size() > max_digits || digits.size() > 19) return std::nullopt;
  std::uint64_t value = 0;
  for (const char c : digits) {
    if (!is_digit(c)) return std::nullopt;
    value = value * 10 + static_cast<std::uint64_t>(c - '0');
  }
  if (value > max_value) return std::nullopt;
  return value;
}

std::optional<std::uint64_t> parse_hex(std::string_view digits, std::size_t max_digits) noexcept {
  if (digits.empty() || digits.size() > max_digits || digits.size() > 16) return std::nullopt;
  std::uint64_t value = 0;
  for (const char c : digits) {
    if (!is_hex_digit(c)) return std::nullopt;
    value = (value << 4U) | static_cast<std::uint64_t>(hex_value(c));
  }
  return value;
}

std::optional<double> parse_decimal(std::string_view field, char separator) noexcept {
  bool negative = false;
  if (!field.empty() && (field.front() == '-' || field.front() == '+')) {
    negative = field.front() == '-';
    field.remove_prefix(1);
  }
  if (field.empty()) return std::nullopt;
  std::uint64_t mantissa = 0;
  int digits = 0;
  int fraction_digits = 0;
  bool seen_separator = false;
  bool seen_integer_digit = false;
  for (const char c : field) {
    if (c == separator && !seen_separator) {
      seen_separator = true;
      continue;
    }
    if (!is_digit(c)) return std::nullopt;
    if (!seen_separator) seen_integer_digit = true;
    if (++digits > 15) return std::nullopt;
    mantissa = mantissa * 10 + static_cast<std::uint64_t>(c - '0');
    if (seen_separator) ++fraction_digits;
  }
  if (!seen_integer_digit || (seen_separator && fraction_digits == 0)) return std::nullopt;
  // One division by an exact power of ten: correctly rounded, and cheaper than a loop.
  static constexpr double powers_of_ten[] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                             1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};
  const double value = static_cast<double>(mantissa) / powers_of_ten[fraction_digits];
  return negative ? -value : value;
}

std::size_t split(std::string_view text, char separator, std::span<std::string_view> out) noexcept {
  std::size_t count = 0;
  while (true) {
    const std::size_t at = text.find(separator);
    if (count == out.size()) return out.size() + 1;
    out[count++] = text.substr(0, at);
    if (at == std::string_view::npos) return count;
    text.remove_prefix(at + 1);
  }
}

void write_hex(std::uint64_t value, std::size_t width, char* out) noexcept {
  static constexpr char digits[] = "0123456789ABCDEF";
  for (std::size_t i = 0; i < width; ++i) {
    out[width - 1 - i] = digits[value & 0xFU];
    value >>= 4U;
  }
}

std::string hex_byte(std::uint8_t value) {
  std::string text(2, '0');
  write_hex(value, 2, text.data());
  return text;
}

namespace {
std::string to_lower_hex(unsigned char byte) {
  constexpr const char* digits = "0123456789abcdef";
  return {digits[byte >> 4], digits[byte & 0x0f]};
}
}  // namespace

std::string printable(std::string_view text, bool ascii_only, std::size_t limit) {
  std::string shown;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (i == limit) {
      shown += "...";
      break;
    }
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte < 0x20 || byte == 0x7f || (ascii_only && byte > 0x7f)) {
      shown += "\\x";
      shown += to_lower_hex(byte);
    } else {
      shown += text[i];
    }
  }
  return shown;
}

namespace {

// Optimal string alignment distance: insertions, deletions, substitutions and swaps of two
// neighbours each cost one; case is ignored.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  const auto lower = [](char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); };
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) && lower(a[i - 2]) == lower(b[j - 1]))
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

}  // namespace

std::optional<std::string> closest(std::string_view typed, std::span<const std::string> candidates) {
  // Past 64 bytes nobody typed a near miss of a setting's name; the table stays small.
  if (typed.empty() || typed.size() > 64) return std::nullopt;
  const std::size_t limit = std::max<std::size_t>(1, typed.size() / 3);
  std::optional<std::string> best;
  std::size_t best_distance = limit + 1;
  bool tie = false;
  for (const std::string& candidate : candidates) {
    if (candidate.size() > 64) continue;
    const std::size_t distance = edit_distance(typed, candidate);
    if (distance < best_distance) {
      best = candidate;
      best_distance = distance;
      tie = false;
    } else if (distance == best_distance && best && *best != candidate) {
      tie = true;
    }
  }
  if (tie || best_distance > limit) return std::nullopt;
  return best;
}

}  // namespace rangekit::text
