#include "rangekit/ls5/identification.hpp"

#include <cmath>
#include <cstdint>
#include <string>

#include "ls5/messages.hpp"
#include "rangekit/core/text.hpp"

namespace rangekit::ls5 {
namespace {

constexpr std::size_t version_at = 0;
constexpr std::size_t lower_at = version_at + identification_version_width + 1;  // after 'b'
constexpr std::size_t range_at = lower_at + identification_lower_width + 1;      // after 'd'
constexpr std::size_t serial_at = range_at + identification_range_width + 3;     // after "s/n"
static_assert(serial_at + identification_serial_width == identification_field_length);

constexpr std::uint32_t max_serial = 9'999'999;

Error id_error(Errc code, const std::string& message) { return make_error(code, "LS5 identification: " + message); }

bool printable(std::string_view text) noexcept {
  for (const char c : text) {
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) return false;
  }
  return true;
}

std::string_view trim_spaces(std::string_view text) noexcept {
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
  return text;
}

// A field like "8,1234": digits, at most one decimal comma, spaces around tolerated (L17).
Result<double> parse_number_field(std::string_view field, const char* what) {
  const std::string_view number = trim_spaces(field);
  const std::optional<double> value =
      (!number.empty() && text::is_digit(number.front())) ? text::parse_decimal(number, ',') : std::nullopt;
  if (!value) {
    return id_error(Errc::bad_number,
                    std::string(what) + " " + detail::quote(field) + " is not a number with a decimal comma");
  }
  return *value;
}

std::uint64_t power_of_ten(std::size_t exponent) noexcept {
  std::uint64_t value = 1;
  for (std::size_t i = 0; i < exponent; ++i) value *= 10;
  return value;
}

// Writes `digits` right-aligned into `out[0, width)` with leading zeros.
void write_padded(std::uint64_t value, std::size_t width, char* out) noexcept {
  for (std::size_t i = 0; i < width; ++i) {
    out[width - 1 - i] = static_cast<char>('0' + value % 10);
    value /= 10;
  }
}

std::size_t digit_count(std::uint64_t value) noexcept {
  std::size_t count = 1;
  while (value >= 10) {
    value /= 10;
    ++count;
  }
  return count;
}

// Exactly `width` characters, decimal comma, as many decimals as fit (L2).
bool format_number_field(double value, std::size_t width, char* out) noexcept {
  if (!std::isfinite(value) || value < 0.0 || value >= static_cast<double>(power_of_ten(width))) return false;
  for (std::size_t decimals = width - 2; decimals > 0; --decimals) {
    const std::uint64_t scale = power_of_ten(decimals);
    const auto scaled = static_cast<std::uint64_t>(std::llround(value * static_cast<double>(scale)));
    const std::uint64_t whole = scaled / scale;
    const std::size_t whole_digits = digit_count(whole);
    if (whole_digits + 1 + decimals > width) continue;
    write_padded(whole, whole_digits, out);
    out[whole_digits] = ',';
    write_padded(scaled % scale, decimals, out + whole_digits + 1);
    return true;
  }
  const auto whole = static_cast<std::uint64_t>(std::llround(value));
  if (digit_count(whole) > width) return false;
  write_padded(whole, width, out);
  return true;
}

}  // namespace

Result<Identification> decode_identification_field(std::string_view field) {
  if (field.size() != identification_field_length) {
    return id_error(field.size() < identification_field_length ? Errc::truncated : Errc::overlong,
                    "the field has " + std::to_string(field.size()) + " characters, expected 35");
  }
  if (!printable(field)) return id_error(Errc::invalid_frame, "control or non-ASCII byte in " + detail::quote(field));

  Identification id;
  std::string_view version = field.substr(version_at, identification_version_width);
  while (!version.empty() && version.back() == ' ') version.remove_suffix(1);
  if (version.empty()) return id_error(Errc::invalid_frame, "the version field is blank");
  id.version_text.assign(version);
  id.version = try_parse_firmware_version(version);

  auto lower = parse_number_field(field.substr(lower_at, identification_lower_width), "lower boundary");
  if (!lower) return std::move(lower).error();
  auto range = parse_number_field(field.substr(range_at, identification_range_width), "range");
  if (!range) return std::move(range).error();
  if (*range <= 0.0) return id_error(Errc::out_of_range, "the range is 0");
  id.lower_boundary_mm = *lower;
  id.range_mm = *range;

  const std::string_view serial = field.substr(serial_at, identification_serial_width);
  const auto serial_value = text::parse_unsigned(serial, identification_serial_width);
  if (!serial_value) {
    return id_error(Errc::bad_number, "serial number " + detail::quote(serial) + " is not 7 decimal digits");
  }
  id.serial_number = static_cast<std::uint32_t>(*serial_value);
  return id;
}

Result<IdentificationField> encode_identification_field(const Identification& id) {
  if (id.version_text.empty() || !printable(id.version_text.view())) {
    return id_error(Errc::wrong_form, "the version text must be 1-10 printable characters");
  }
  if (id.serial_number > max_serial) {
    return id_error(Errc::out_of_range,
                    "serial number " + std::to_string(id.serial_number) + " has more than 7 digits");
  }
  char field[identification_field_length];
  std::size_t at = 0;
  for (; at < id.version_text.size(); ++at) field[at] = id.version_text.view()[at];
  for (; at < identification_version_width; ++at) field[at] = ' ';
  field[lower_at - 1] = 'b';
  if (!format_number_field(id.lower_boundary_mm, identification_lower_width, field + lower_at)) {
    return id_error(Errc::out_of_range,
                    "lower boundary " + std::to_string(id.lower_boundary_mm) + " mm does not fit 6 characters");
  }
  field[range_at - 1] = 'd';
  if (!(id.range_mm > 0.0) || !format_number_field(id.range_mm, identification_range_width, field + range_at)) {
    return id_error(Errc::out_of_range,
                    "range " + std::to_string(id.range_mm) + " mm is not positive or does not fit 7 characters");
  }
  field[serial_at - 3] = 's';
  field[serial_at - 2] = '/';
  field[serial_at - 1] = 'n';
  write_padded(id.serial_number, identification_serial_width, field + serial_at);

  IdentificationField text;
  text.assign(std::string_view(field, identification_field_length));
  return text;
}

Result<Identification> make_identification(std::string_view version_text, double lower_boundary_mm, double range_mm,
                                           std::uint32_t serial_number) {
  if (version_text.empty() || version_text.size() > identification_version_width || !printable(version_text)) {
    return id_error(Errc::wrong_form,
                    "the version text must be 1-10 printable characters, got " + detail::quote(version_text));
  }
  Identification id;
  id.version_text.assign(version_text);
  id.version = try_parse_firmware_version(version_text);
  id.lower_boundary_mm = lower_boundary_mm;
  id.range_mm = range_mm;
  id.serial_number = serial_number;
  auto field = encode_identification_field(id);  // the same checks the encoder makes
  if (!field) return std::move(field).error();
  return id;
}

}  // namespace rangekit::ls5
