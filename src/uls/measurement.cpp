// Measurement lines (§8 p.23-24, §9 p.39-41; U8-U13, U27, U31, U32).
#include "rangekit/uls/measurement.hpp"

#include <algorithm>
#include <string>

#include "rangekit/core/text.hpp"
#include "rangekit/uls/formulas.hpp"
#include "uls/fields.hpp"

namespace rangekit::uls {
namespace {

Error line_error(Errc code, const std::string& what) { return make_error(code, "ULS measurement: " + what); }

int decimals_for(Units units) noexcept { return units == Units::metres ? 3 : 2; }
const char* units_word(Units units) noexcept { return units == Units::metres ? "metres" : "feet"; }

// The common case of read_range below, without a Result: true only for a range it
// accepts, with the same value. One pass that checks and converts.
bool read_good_range(std::string_view field, Units units, Range& out) noexcept {
  if (field.size() > max_range_chars) return false;
  std::size_t i = 0;
  const bool negative = !field.empty() && field.front() == '-';
  if (negative) ++i;
  std::uint64_t mantissa = 0;
  std::size_t integer_digits = 0;
  std::size_t fraction_digits = 0;
  bool point = false;
  for (; i < field.size(); ++i) {
    const char c = field[i];
    if (c == '.' && !point) {
      point = true;
      continue;
    }
    if (!text::is_digit(c)) return false;
    mantissa = mantissa * 10 + static_cast<std::uint64_t>(c - '0');
    ++(point ? fraction_digits : integer_digits);
  }
  if (!point || integer_digits == 0 || static_cast<int>(fraction_digits) != decimals_for(units)) return false;
  const double magnitude = static_cast<double>(mantissa) / (fraction_digits == 3 ? 1000.0 : 100.0);
  // Field by field, as make_range would: a Range returned through memory and
  // copied stalled on store forwarding.
  out.user = negative ? -magnitude : magnitude;
  out.metres = to_metres(out.user, units);
  out.units = units;
  return true;
}

// The common case of read_unsigned below: 1 to max_digits (at most 9) digits, at most max_value.
bool read_good_unsigned(std::string_view field, std::size_t max_digits, std::uint32_t max_value,
                        std::uint32_t& out) noexcept {
  if (field.empty() || field.size() > max_digits) return false;
  std::uint32_t value = 0;
  for (const char c : field) {
    if (!text::is_digit(c)) return false;
    value = value * 10 + static_cast<std::uint32_t>(c - '0');
  }
  if (value > max_value) return false;
  out = value;
  return true;
}

// "[-]digits.ddd" (metres) or "[-]digits.dd" (feet), at most 8 characters (U9, U27).
Result<Range> read_range(std::string_view field, Units units) {
  if (field.size() > max_range_chars) {
    return line_error(Errc::overlong, "range " + detail::quoted(field) + " longer than 8 characters");
  }
  std::size_t i = 0;
  const bool negative = !field.empty() && field.front() == '-';
  if (negative) ++i;
  std::uint64_t mantissa = 0;
  std::size_t integer_digits = 0;
  std::size_t fraction_digits = 0;
  bool point = false;
  bool number = true;
  for (; i < field.size(); ++i) {
    const char c = field[i];
    if (c == '.' && !point) {
      point = true;
      continue;
    }
    if (!text::is_digit(c)) {
      number = false;
      break;
    }
    mantissa = mantissa * 10 + static_cast<std::uint64_t>(c - '0');
    ++(point ? fraction_digits : integer_digits);
  }
  if (!point && number && integer_digits > 0) {
    return line_error(Errc::wrong_form, "range " + detail::quoted(field) + " has no decimal point");
  }
  if (!number || !point || integer_digits == 0 || fraction_digits == 0) {
    return line_error(Errc::bad_number, "range " + detail::quoted(field) + " is not a number");
  }
  if (static_cast<int>(fraction_digits) != decimals_for(units)) {
    return line_error(Errc::wrong_form, "range " + detail::quoted(field) + " has " + std::to_string(fraction_digits) +
                                            " decimals; " + units_word(units) + " are written with " +
                                            std::to_string(decimals_for(units)));
  }
  const double magnitude = static_cast<double>(mantissa) / (fraction_digits == 3 ? 1000.0 : 100.0);
  return make_range(negative ? -magnitude : magnitude, units);
}

Result<std::uint32_t> read_unsigned(std::string_view field, std::size_t max_digits, std::uint64_t max_value,
                                    const char* what) {
  const std::optional<std::uint64_t> value = text::parse_unsigned(field, max_digits, max_value);
  if (value) return static_cast<std::uint32_t>(*value);
  for (const char c : field) {
    if (!text::is_digit(c)) {
      return line_error(Errc::bad_number, std::string(what) + " " + detail::quoted(field) + " is not a number");
    }
  }
  return line_error(field.size() > max_digits ? Errc::overlong : Errc::out_of_range,
                    std::string(what) + " " + detail::quoted(field) + " is above " + std::to_string(max_value));
}

Error wrong_field_count(const char* line, std::size_t got, std::size_t want) {
  return line_error(got < want ? Errc::truncated : Errc::overlong,
                    std::string(line) + " has " + std::to_string(got) + " fields, needs " + std::to_string(want));
}

Result<Reading> decode_averaging(std::span<const std::string_view> fields, const MeasurementContext& context) {
  AveragingReading reading;
  switch (context.display) {
    case DisplayMode::range: {
      if (fields.size() != 1) return wrong_field_count("averaging line (display range)", fields.size(), 1);
      auto range = read_range(fields[0], context.units);
      if (!range) return std::move(range).error();
      reading.range = *range;
      break;
    }
    case DisplayMode::intensity: {
      if (fields.size() != 1) return wrong_field_count("averaging line (display intensity)", fields.size(), 1);
      if (fields[0].find('.') != std::string_view::npos) {
        return line_error(Errc::wrong_form, "pulse width " + detail::quoted(fields[0]) +
                                                " has a decimal point; display mode 3 sends pulse width only");
      }
      auto width = read_unsigned(fields[0], max_pulse_width_digits, 9'999'999, "pulse width");
      if (!width) return std::move(width).error();
      reading.pulse_width_ps = *width;
      break;
    }
    case DisplayMode::range_and_intensity: {
      if (fields.size() != 2)
        return wrong_field_count("averaging line (display range-and-intensity)", fields.size(), 2);
      auto range = read_range(fields[0], context.units);
      if (!range) return std::move(range).error();
      auto width = read_unsigned(fields[1], max_pulse_width_digits, 9'999'999, "pulse width");
      if (!width) return std::move(width).error();
      reading.range = *range;
      reading.pulse_width_ps = *width;
      break;
    }
    default:
      return line_error(Errc::out_of_range,
                        "display mode " + std::to_string(static_cast<int>(context.display)) + " is not 1-3");
  }
  return Reading{reading};
}

Result<Reading> decode_binning(std::span<const std::string_view> fields, Units units) {
  if (fields.size() != 4) return wrong_field_count("binning line", fields.size(), 4);
  auto index = read_unsigned(fields[0], 2, max_binning_targets - 1, "target index");
  if (!index) return std::move(index).error();
  auto count = read_unsigned(fields[1], 2, max_binning_targets, "target count");
  if (!count) return std::move(count).error();
  if (*count == 0 || *index >= *count) {
    return line_error(Errc::out_of_range,
                      "target index " + std::to_string(*index) + " is not below count " + std::to_string(*count));
  }
  auto range = read_range(fields[2], units);
  if (!range) return std::move(range).error();
  auto strength = read_unsigned(fields[3], max_strength_digits, 65535, "strength");
  if (!strength) return std::move(strength).error();
  return Reading{
      BinningTarget{static_cast<std::uint8_t>(*index), static_cast<std::uint8_t>(*count), *range, *strength}};
}

Result<Reading> decode_look_down(std::span<const std::string_view> fields) {
  if (fields.size() != 1) return wrong_field_count("look-down line", fields.size(), 1);
  if (fields[0] == "0") return Reading{LookDownReading{false}};
  if (fields[0] == "1") return Reading{LookDownReading{true}};
  return line_error(Errc::out_of_range, "look-down state " + detail::quoted(fields[0]) + " is not 0 or 1");
}

Result<Reading> decode_event(std::string_view text) {
  if (text == "0") return Reading{TimeBetweenEvents{TimeBetweenEvents::Kind::no_presence, 0}};
  const std::optional<std::uint64_t> pulses = text::parse_hex(text, 4);
  if (text.size() != 4 || !pulses) {
    return line_error(Errc::bad_hex, "time between events " + detail::quoted(text) + " is not 4 hex digits");
  }
  if (*pulses == 0) return Reading{TimeBetweenEvents{TimeBetweenEvents::Kind::overflow, 0}};
  return Reading{TimeBetweenEvents{TimeBetweenEvents::Kind::pulses, static_cast<std::uint16_t>(*pulses)}};
}

Result<Reading> decode_error_line(std::span<const std::string_view> fields) {
  if (fields.size() != 1) return wrong_field_count("error line", fields.size(), 1);
  auto number = read_unsigned(fields[0], 3, 999, "error number");
  if (!number) return std::move(number).error();
  if (*number == 0) return line_error(Errc::out_of_range, "error number 0 is not an error (U31)");
  return Reading{MeasurementError{static_cast<int>(*number)}};
}

Result<Reading> decode_reading(const FrameView& frame, const MeasurementContext& context) {
  const bool events_expected = context.mode == Mode::look_down && context.time_between_events;
  if (frame.kind == FrameKind::time_between_events) {
    if (!events_expected) {
      return line_error(Errc::wrong_form,
                        "time-between-events frame, but the unit is not in look down with TB on (U32)");
    }
    return decode_event(frame.event_text);
  }
  if (frame.is("ER")) return decode_error_line(frame.fields());
  if (!frame.is("BM")) {
    return line_error(Errc::wrong_form, "mnemonic " + detail::quoted(frame.mnemonic) + " is not BM or ER");
  }
  switch (context.mode) {
    case Mode::averaging:
      return decode_averaging(frame.fields(), context);
    case Mode::binning:
      return decode_binning(frame.fields(), context.units);
    case Mode::look_down:
      if (events_expected) {
        return line_error(Errc::wrong_form, "BM line in look down with time between events on (U32)");
      }
      return decode_look_down(frame.fields());
  }
  return line_error(Errc::out_of_range,
                    "measurement mode " + std::to_string(static_cast<int>(context.mode)) + " is not 1-3");
}

// A range in its field, or an error when it does not fit §9's width (U27).
Result<FieldText> range_field(const Range& range) {
  const std::optional<FieldText> text = format_distance(range.user, range.units);
  if (!text || text->size > max_range_chars) {
    return line_error(Errc::out_of_range, "range " + std::to_string(range.user) + " " + units_word(range.units) +
                                              " does not fit the 8-character field");
  }
  return *text;
}

Result<FieldText> pulse_width_field(std::uint32_t picoseconds) {
  const FieldText text = format_unsigned(picoseconds);
  if (text.size > max_pulse_width_digits) {
    return line_error(Errc::out_of_range, "pulse width " + std::to_string(picoseconds) + " ps has more than 7 digits");
  }
  return text;
}

}  // namespace

Range make_range(double user_value, Units units) noexcept { return {user_value, to_metres(user_value, units), units}; }

namespace {

// The lines a measuring unit streams (averaging and binning BM lines, ER lines),
// read straight into `reading`. True only when decode_reading would give the same
// reading; everything else goes through decode_reading, which names the problem.
// Fields: a FrameView's fields() or a detail::CommonFrame.
template <class Fields>
bool decode_common_reading(std::string_view mnemonic, const Fields& fields, const MeasurementContext& context,
                           Reading& reading) {
  if (mnemonic.size() != 2) return false;
  const char first = text::to_upper(mnemonic[0]);
  const char second = text::to_upper(mnemonic[1]);
  std::uint32_t number = 0;
  if (first == 'E' && second == 'R') {  // U13, U31
    if (fields.size() != 1 || !read_good_unsigned(fields[0], 3, 999, number) || number == 0) return false;
    reading.emplace<MeasurementError>(MeasurementError{static_cast<int>(number)});
    return true;
  }
  if (first != 'B' || second != 'M') return false;
  Range range;
  switch (context.mode) {
    case Mode::averaging: {
      const bool with_range = context.display != DisplayMode::intensity;
      const bool with_width = context.display != DisplayMode::range;
      if ((context.display != DisplayMode::range && context.display != DisplayMode::range_and_intensity &&
           context.display != DisplayMode::intensity) ||
          fields.size() != (with_range && with_width ? 2U : 1U)) {
        return false;
      }
      if (with_range && !read_good_range(fields[0], context.units, range)) return false;
      if (with_width && !read_good_unsigned(fields[fields.size() - 1], max_pulse_width_digits, 9'999'999, number))
        return false;
      AveragingReading& averaging = reading.emplace<AveragingReading>();
      if (with_range) averaging.range = range;
      if (with_width) averaging.pulse_width_ps = number;
      return true;
    }
    case Mode::binning: {
      std::uint32_t index = 0;
      std::uint32_t strength = 0;
      if (fields.size() != 4 || !read_good_unsigned(fields[0], 2, max_binning_targets - 1, index) ||
          !read_good_unsigned(fields[1], 2, max_binning_targets, number) || number == 0 || index >= number ||
          !read_good_range(fields[2], context.units, range) ||
          !read_good_unsigned(fields[3], max_strength_digits, 65535, strength)) {
        return false;
      }
      reading.emplace<BinningTarget>(
          BinningTarget{static_cast<std::uint8_t>(index), static_cast<std::uint8_t>(number), range, strength});
      return true;
    }
    case Mode::look_down:
      break;
  }
  return false;
}

// Every line, with the message that names what is wrong with a bad one.
// Kept out of line: inlined, its stack frame made every good line pay for it.
[[gnu::noinline]] Result<Measurement> decode_checked(const FrameView& frame, const MeasurementContext& context) {
  if (frame.address.is_broadcast()) {
    return line_error(Errc::wrong_form, "line from broadcast address " + detail::hex_byte(frame.address.byte) +
                                            " (units never send from one, U4)");
  }
  Result<Reading> reading = decode_reading(frame, context);
  if (!reading) return std::move(reading).error();
  return Measurement{frame.address, *reading};
}

}  // namespace

// Both overloads read a line straight into the Result they return (one object,
// returned by name on every path, so it is built in the caller's slot): no
// Reading -> Measurement -> Result copies per line.
Result<Measurement> decode_measurement(const FrameView& frame, const MeasurementContext& context) {
  Result<Measurement> decoded = Measurement{frame.address, Reading{}};
  if (frame.address.is_broadcast() || frame.kind != FrameKind::message ||
      !decode_common_reading(frame.mnemonic, frame.fields(), context, decoded->reading)) {
    decoded = decode_checked(frame, context);
  }
  return decoded;
}

Result<Measurement> decode_measurement(Bytes frame, const MeasurementContext& context) {
  static const Measurement blank{};  // copied whole: see parse_reply in src/ls5/reply.cpp
  Result<Measurement> decoded = blank;
  detail::CommonFrame common;
  if (detail::parse_common_frame(as_text(frame), common) && !common.address.is_broadcast() &&
      decode_common_reading(common.mnemonic(), common, context, decoded->reading)) {
    decoded->source = common.address;
  } else if (Result<FrameView> view = parse_frame(frame); view) {
    decoded = decode_checked(*view, context);
  } else {
    decoded = std::move(view).error();
  }
  return decoded;
}

std::size_t detail::read_good_averaging_line(Bytes pending, const MeasurementContext& context, Measurement& out) {
  const bool with_range = context.display != DisplayMode::intensity;
  const bool with_width = context.display != DisplayMode::range;
  if (context.mode != Mode::averaging ||
      (context.display != DisplayMode::range && context.display != DisplayMode::range_and_intensity &&
       context.display != DisplayMode::intensity)) {
    return 0;
  }
  const std::string_view line = as_text(pending);
  Address source{};  // as decode_measurement leaves a '$' line's source
  std::size_t at = 1;
  if (line.size() < 2) return 0;
  if (line[0] == '#') {
    // A unit address below DEL: scan_frame hands such a frame out whole up to its CR.
    const auto address = static_cast<std::uint8_t>(line[1]);
    if (address < first_unit_address || address >= 0x7F) return 0;
    source = Address::unit(address);
    if (source.is_broadcast()) return 0;
    at = 2;
  } else if (line[0] != '$') {
    return 0;
  }
  if (line.size() < at + 3 || text::to_upper(line[at]) != 'B' || text::to_upper(line[at + 1]) != 'M' ||
      line[at + 2] != ',') {
    return 0;
  }
  at += 3;
  // The next field: up to the ',' or CR that ends it, at most max_chars long. The
  // readers below take only digits, '.' and a leading '-', so every byte of a line
  // taken here is one scan_frame's fast path passes.
  auto next_field = [&](std::size_t max_chars, char terminator, std::string_view& field) {
    const std::size_t limit = std::min(line.size(), at + max_chars + 1);
    for (std::size_t end = at; end < limit; ++end) {
      if (line[end] == terminator) {
        field = line.substr(at, end - at);
        at = end + 1;
        return true;
      }
    }
    return false;
  };
  std::string_view field;
  Range range;
  std::uint32_t width = 0;
  if (with_range &&
      (!next_field(max_range_chars, with_width ? ',' : '\r', field) || !read_good_range(field, context.units, range))) {
    return 0;
  }
  if (with_width && (!next_field(max_pulse_width_digits, '\r', field) ||
                     !read_good_unsigned(field, max_pulse_width_digits, 9'999'999, width))) {
    return 0;
  }
  out.source = source;
  AveragingReading& averaging = out.reading.emplace<AveragingReading>();
  if (with_range) averaging.range = range;
  if (with_width) averaging.pulse_width_ps = width;
  return at;
}

Result<FrameText> encode_averaging(Address address, const AveragingReading& reading) {
  std::array<std::string_view, 2> fields{};
  std::size_t count = 0;
  FieldText range_text;
  FieldText width_text;
  if (reading.range) {
    auto text = range_field(*reading.range);
    if (!text) return std::move(text).error();
    range_text = *text;
    fields[count++] = range_text.view();
  }
  if (reading.pulse_width_ps) {
    auto text = pulse_width_field(*reading.pulse_width_ps);
    if (!text) return std::move(text).error();
    width_text = *text;
    fields[count++] = width_text.view();
  }
  if (count == 0) return line_error(Errc::truncated, "averaging reading without range or pulse width");
  return encode_frame(address, "BM", {fields.data(), count});
}

Result<FrameText> encode_binning_target(Address address, const BinningTarget& target) {
  if (target.count == 0 || target.count > max_binning_targets || target.index >= target.count) {
    return line_error(Errc::out_of_range, "target " + std::to_string(target.index) + " of " +
                                              std::to_string(target.count) + " is not index < count <= 15");
  }
  if (target.strength > 65535) {
    return line_error(Errc::out_of_range, "strength " + std::to_string(target.strength) + " is above 65535");
  }
  auto range = range_field(target.range);
  if (!range) return std::move(range).error();
  const FieldText index = format_unsigned(target.index);
  const FieldText count = format_unsigned(target.count);
  const FieldText strength = format_unsigned(target.strength);
  const std::array<std::string_view, 4> fields{index.view(), count.view(), range->view(), strength.view()};
  return encode_frame(address, "BM", fields);
}

Result<FrameText> encode_look_down(Address address, bool present) {
  const std::string_view field = present ? "1" : "0";
  return encode_frame(address, "BM", {&field, 1});
}

Result<FrameText> encode_measurement_error(Address address, int error_number) {
  return encode_error_reply(address, error_number);
}

Result<FrameText> encode_measurement(Address address, const Reading& reading) {
  if (const auto* averaging = std::get_if<AveragingReading>(&reading)) return encode_averaging(address, *averaging);
  if (const auto* target = std::get_if<BinningTarget>(&reading)) return encode_binning_target(address, *target);
  if (const auto* look_down = std::get_if<LookDownReading>(&reading)) {
    return encode_look_down(address, look_down->present);
  }
  if (const auto* event = std::get_if<TimeBetweenEvents>(&reading)) return encode_time_between_events(address, *event);
  return encode_measurement_error(address, std::get<MeasurementError>(reading).number);
}

}  // namespace rangekit::uls
