// Encoders for requests and replies (§8): everything parse_frame accepts can be
// written, nothing it refuses is written. No allocation on success.
#include <cmath>
#include <string>

#include "rangekit/core/text.hpp"
#include "rangekit/uls/frame.hpp"
#include "uls/fields.hpp"

namespace rangekit::uls {
namespace {

Error encode_error(Errc code, const std::string& what) { return make_error(code, "ULS encode: " + what); }

bool looks_like_event(std::string_view upper_mnemonic) noexcept {
  if (upper_mnemonic.size() != 4) return false;
  for (const char c : upper_mnemonic) {
    if (!(c >= 'A' && c <= 'F')) return false;
  }
  return true;
}

Result<FrameText> start_frame(Address address) {
  FrameText text;
  if (!address.addressed) {
    text.append('$');
    return text;
  }
  if (address.byte < first_unit_address) {
    return encode_error(Errc::out_of_range, "address byte " + detail::hex_byte(address.byte) + " below 0x30");
  }
  text.append('#');
  text.append(static_cast<char>(address.byte));
  return text;
}

// A field byte is printable ASCII other than the separator and the start bytes;
// the single value of a UA set may be any byte from 0x7F (U25).
std::optional<std::string> field_problem(std::string_view mnemonic, std::span<const std::string_view> fields,
                                         std::size_t index) {
  const std::string_view field = fields[index];
  if (field.empty()) return "field " + std::to_string(index + 1) + " is empty";
  const bool unit_address_value = fields.size() == 1 && field.size() == 1 &&
                                  detail::equal_ignoring_case(mnemonic, "UA") &&
                                  static_cast<std::uint8_t>(field.front()) >= 0x7F;
  if (unit_address_value) return std::nullopt;
  for (const char c : field) {
    const auto byte = static_cast<std::uint8_t>(c);
    if (byte < 0x20 || byte >= 0x7F || c == ',' || c == '$' || c == '#') {
      return "field " + std::to_string(index + 1) + " " + detail::quoted(field) + " holds byte " +
             detail::hex_byte(byte);
    }
  }
  return std::nullopt;
}

}  // namespace

bool FrameText::append(std::string_view text) noexcept {
  if (size_ + text.size() > capacity) return false;
  for (const char c : text) data_[size_++] = c;
  return true;
}

bool FrameText::append(char c) noexcept { return append(std::string_view(&c, 1)); }

FieldText format_unsigned(std::uint64_t value) noexcept {
  FieldText text;
  text.size = detail::write_unsigned(value, text.chars.data());
  return text;
}

std::optional<FieldText> format_distance(double value, Units units) noexcept {
  const int decimals = units == Units::metres ? 3 : 2;
  const double scale = units == Units::metres ? 1000.0 : 100.0;
  if (!std::isfinite(value) || std::fabs(value) >= 1e12) return std::nullopt;
  const auto scaled = static_cast<std::int64_t>(std::llround(value * scale));
  FieldText text;
  text.size = detail::write_fixed(scaled, decimals, text.chars.data());
  return text;
}

Result<FrameText> encode_frame(Address address, std::string_view mnemonic, std::span<const std::string_view> fields) {
  if (mnemonic.size() < min_mnemonic_length || mnemonic.size() > max_mnemonic_length) {
    return encode_error(Errc::invalid_frame, "mnemonic " + detail::quoted(mnemonic) + " is not 2 to 4 letters");
  }
  char upper[max_mnemonic_length];
  for (std::size_t i = 0; i < mnemonic.size(); ++i) {
    if (!text::is_letter(mnemonic[i])) {
      return encode_error(Errc::invalid_frame, "mnemonic " + detail::quoted(mnemonic) + " holds a non-letter");
    }
    upper[i] = text::to_upper(mnemonic[i]);
  }
  const std::string_view upper_mnemonic(upper, mnemonic.size());
  if (fields.empty() && looks_like_event(upper_mnemonic)) {
    return encode_error(Errc::invalid_frame, "mnemonic " + detail::quoted(upper_mnemonic) +
                                                 " alone would read as time between events (U26)");
  }
  if (fields.size() > max_fields) {
    return encode_error(Errc::overlong,
                        std::to_string(fields.size()) + " fields, more than " + std::to_string(max_fields));
  }
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (auto problem = field_problem(mnemonic, fields, i)) return encode_error(Errc::invalid_frame, *problem);
  }

  Result<FrameText> started = start_frame(address);
  if (!started) return started;
  FrameText text = *started;
  text.append(upper_mnemonic);
  bool fits = true;
  for (const std::string_view field : fields) fits = fits && text.append(',') && text.append(field);
  if (!fits || text.size() > max_frame_length) {
    return encode_error(Errc::overlong, "frame longer than " + std::to_string(max_frame_length) + " bytes");
  }
  text.append('\r');
  return text;
}

Result<FrameText> encode_get(Address address, std::string_view mnemonic, std::span<const std::string_view> arguments) {
  return encode_frame(address, mnemonic, arguments);
}

Result<FrameText> encode_action(Address address, std::string_view mnemonic) { return encode_frame(address, mnemonic); }

Result<FrameText> encode_set(Address address, std::string_view mnemonic, std::span<const std::string_view> values) {
  if (values.empty()) return encode_error(Errc::truncated, "a set needs at least one value");
  return encode_frame(address, mnemonic, values);
}

Result<FrameText> encode_set(Address address, std::string_view mnemonic, std::uint64_t value) {
  const FieldText text = format_unsigned(value);
  const std::string_view field = text.view();
  return encode_frame(address, mnemonic, {&field, 1});
}

Result<FrameText> encode_ok(Address address) { return encode_frame(address, "OK"); }

Result<FrameText> encode_error_reply(Address address, int error_number) {
  if (error_number < 0 || error_number > 999) {
    return encode_error(Errc::out_of_range, "error number " + std::to_string(error_number) + " is not 0-999");
  }
  const FieldText text = format_unsigned(static_cast<std::uint64_t>(error_number));
  const std::string_view field = text.view();
  return encode_frame(address, "ER", {&field, 1});
}

Result<FrameText> encode_value_reply(Address address, std::string_view mnemonic,
                                     std::span<const std::string_view> values) {
  if (values.empty()) return encode_error(Errc::truncated, "a value reply needs at least one value");
  return encode_frame(address, mnemonic, values);
}

Result<FrameText> encode_time_between_events(Address address, const TimeBetweenEvents& event) {
  char digits[4] = {'0', '0', '0', '0'};
  std::string_view body;
  switch (event.kind) {
    case TimeBetweenEvents::Kind::no_presence:
      body = "0";
      break;
    case TimeBetweenEvents::Kind::overflow:
      body = {digits, 4};
      break;
    case TimeBetweenEvents::Kind::pulses:
      if (event.pulses == 0) {
        return encode_error(Errc::out_of_range, "0 pulses between events would read as overflow (U12)");
      }
      text::write_hex(event.pulses, 4, digits);
      body = {digits, 4};
      break;
  }
  Result<FrameText> started = start_frame(address);
  if (!started) return started;
  FrameText text = *started;
  text.append(body);
  text.append('\r');
  return text;
}

}  // namespace rangekit::uls
