#include "uls/fields.hpp"

#include "rangekit/core/text.hpp"

namespace rangekit::uls::detail {

bool equal_ignoring_case(std::string_view a, std::string_view b) noexcept {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (text::to_upper(a[i]) != text::to_upper(b[i])) return false;
  }
  return true;
}

bool IntegerField::within(std::int64_t min, std::int64_t max) const noexcept {
  if (!is_number) return false;
  if (negative) {
    if (magnitude == 0) return min <= 0 && 0 <= max;
    if (magnitude > static_cast<std::uint64_t>(INT64_MAX)) return false;
    const std::int64_t value = -static_cast<std::int64_t>(magnitude);
    return min <= value && value <= max;
  }
  if (max < 0 || magnitude > static_cast<std::uint64_t>(max)) return false;
  return static_cast<std::int64_t>(magnitude) >= min;
}

IntegerField read_integer(std::string_view field) noexcept {
  IntegerField result;
  if (!field.empty() && field.front() == '-') {
    result.negative = true;
    field.remove_prefix(1);
  }
  if (field.empty()) return {};
  for (const char c : field) {
    if (!text::is_digit(c)) return {};
    const auto digit = static_cast<std::uint64_t>(c - '0');
    if (result.magnitude > (UINT64_MAX - digit) / 10) {
      result.magnitude = UINT64_MAX;  // saturate: still a number, just too large
    } else {
      result.magnitude = result.magnitude * 10 + digit;
    }
  }
  result.is_number = true;
  return result;
}

std::size_t write_unsigned(std::uint64_t value, char* out) noexcept {
  char reversed[20];
  std::size_t count = 0;
  do {
    reversed[count++] = static_cast<char>('0' + value % 10);
    value /= 10;
  } while (value != 0);
  for (std::size_t i = 0; i < count; ++i) out[i] = reversed[count - 1 - i];
  return count;
}

std::size_t write_fixed(std::int64_t scaled, int decimals, char* out) noexcept {
  std::size_t size = 0;
  std::uint64_t magnitude = 0;
  if (scaled < 0) {
    out[size++] = '-';
    magnitude = static_cast<std::uint64_t>(-(scaled + 1)) + 1;
  } else {
    magnitude = static_cast<std::uint64_t>(scaled);
  }
  std::uint64_t divisor = 1;
  for (int i = 0; i < decimals; ++i) divisor *= 10;
  size += write_unsigned(magnitude / divisor, out + size);
  if (decimals > 0) {
    out[size++] = '.';
    std::uint64_t fraction = magnitude % divisor;
    for (int i = decimals - 1; i >= 0; --i) {
      out[size + static_cast<std::size_t>(i)] = static_cast<char>('0' + fraction % 10);
      fraction /= 10;
    }
    size += static_cast<std::size_t>(decimals);
  }
  return size;
}

std::string hex_byte(std::uint8_t byte) { return "0x" + text::hex_byte(byte); }

std::string quoted(std::string_view whole) {
  // Longer than any frame (a whole junk buffer handed to a line parser): cut, so a
  // message stays a line and costs no more than a frame's worth.
  const std::string_view field = whole.substr(0, max_quoted_bytes);
  std::string text = "'";
  text.reserve(field.size() + 24);
  for (const char c : field) {
    const auto byte = static_cast<std::uint8_t>(c);
    if (byte < 0x20 || byte >= 0x7F) {
      text += "\\x";
      char digits[2];
      text::write_hex(byte, 2, digits);
      text.append(digits, 2);
    } else {
      text += c;
    }
  }
  text += "'";
  if (whole.size() > field.size()) text += "... (" + std::to_string(whole.size()) + " bytes)";
  return text;
}

}  // namespace rangekit::uls::detail
