// parse_frame: one ULS frame (without CR) into a FrameView (§8, U4, U12, U25, U26, U28).
#include <string>

#include "rangekit/core/text.hpp"
#include "rangekit/uls/frame.hpp"
#include "uls/fields.hpp"

namespace rangekit::uls {
namespace {

Error frame_error(Errc code, const std::string& what) { return make_error(code, "ULS frame: " + what); }

bool is_upper_hex(char c) noexcept { return text::is_digit(c) || (c >= 'A' && c <= 'F'); }

// U12/U26: "0" or exactly four upper-case hex digits, no comma.
bool is_time_between_events(std::string_view body) noexcept {
  if (body == "0") return true;
  if (body.size() != 4) return false;
  for (const char c : body) {
    if (!is_upper_hex(c)) return false;
  }
  return true;
}

// U25: the one byte of a UA set's value may be 0x7F-0xFF.
bool is_unit_address_value(std::string_view body, std::size_t offset) noexcept {
  return body.size() == 4 && offset == 3 && detail::equal_ignoring_case(body.substr(0, 3), "UA,");
}

std::string describe_byte(std::uint8_t byte, std::size_t offset) {
  const std::string at = " at offset " + std::to_string(offset);
  if (byte == 0) return "embedded NUL" + at;
  if (byte == '\r') return "CR inside the frame" + at;
  if (byte == '\n') return "line feed" + at + " (frames end with CR)";
  if (byte < 0x20) return "control byte " + detail::hex_byte(byte) + at;
  if (byte == '$' || byte == '#') return std::string("start byte '") + static_cast<char>(byte) + "'" + at;
  return "non-ASCII byte " + detail::hex_byte(byte) + at;
}

// Fills `view` in place (it is large; copying it per frame shows on the hot path).
Status parse_body(FrameView& view, std::string_view body, std::size_t body_offset) {
  if (body.empty()) return frame_error(Errc::truncated, "empty mnemonic");
  for (std::size_t i = 0; i < body.size(); ++i) {
    const auto byte = static_cast<std::uint8_t>(body[i]);
    if (byte > '$' && byte < 0x7F) continue;  // digits, letters, ',' and '.': the common case
    const bool printable = byte >= 0x20 && byte < 0x7F && byte != '$' && byte != '#';
    if (!printable && !(byte >= 0x7F && is_unit_address_value(body, i))) {
      return frame_error(Errc::invalid_frame, describe_byte(byte, body_offset + i));
    }
  }
  if (is_time_between_events(body)) {
    view.kind = FrameKind::time_between_events;
    view.event_text = body;
    return ok_status();
  }

  const std::size_t comma = body.find(',');
  const std::string_view mnemonic = body.substr(0, comma);
  if (mnemonic.empty()) return frame_error(Errc::truncated, "empty mnemonic");
  if (comma == std::string_view::npos && text::is_digit(body.front())) {
    // Only a time between events starts with a digit and has no comma (U12).
    return frame_error(Errc::bad_hex,
                       "time between events " + detail::quoted(body) + " is not '0' or 4 upper-case hex digits");
  }
  for (const char c : mnemonic) {
    if (!text::is_letter(c)) {
      return frame_error(Errc::invalid_frame, "mnemonic " + detail::quoted(mnemonic) + " holds a non-letter");
    }
  }
  if (mnemonic.size() < min_mnemonic_length || mnemonic.size() > max_mnemonic_length) {
    return frame_error(Errc::invalid_frame, "mnemonic " + detail::quoted(mnemonic) + " is not 2 to 4 letters");
  }
  view.mnemonic = mnemonic;
  if (comma == std::string_view::npos) return ok_status();

  const std::size_t count = text::split(body.substr(comma + 1), ',', view.field_slots);
  if (count > max_fields) {
    return frame_error(Errc::overlong, "more than " + std::to_string(max_fields) + " fields");
  }
  view.field_count = count;
  for (std::size_t i = 0; i < count; ++i) {
    if (view.field_slots[i].empty()) {
      return frame_error(Errc::invalid_frame, "field " + std::to_string(i + 1) + " is empty");
    }
  }
  return ok_status();
}

}  // namespace

bool FrameView::is(std::string_view upper_mnemonic) const noexcept {
  return kind == FrameKind::message && detail::equal_ignoring_case(mnemonic, upper_mnemonic);
}

bool detail::parse_common_frame(std::string_view frame, CommonFrame& out) noexcept {
  if (frame.size() < 5 || frame.size() > max_frame_length) return false;  // "$BM,1" is the shortest
  std::size_t at = 1;
  if (frame[0] == '#') {
    const auto address = static_cast<std::uint8_t>(frame[1]);
    if (address < first_unit_address) return false;
    out.address = Address::unit(address);
    at = 2;
  } else if (frame[0] != '$') {
    return false;
  }
  out.text = frame;
  out.mnemonic_at = at;
  while (at < frame.size() && text::is_letter(frame[at])) ++at;
  out.mnemonic_size = at - out.mnemonic_at;
  if (out.mnemonic_size < min_mnemonic_length || out.mnemonic_size > max_mnemonic_length || at == frame.size() ||
      frame[at] != ',') {
    return false;  // no fields, or not a mnemonic: the full checks decide
  }
  std::size_t count = 0;
  std::size_t field_at = ++at;
  for (;; ++at) {
    if (at == frame.size() || frame[at] == ',') {
      if (at == field_at || count == max_fields) return false;  // empty field, too many fields
      out.starts[count++] = static_cast<std::uint8_t>(field_at);
      field_at = at + 1;
      if (at == frame.size()) break;
      continue;
    }
    const auto byte = static_cast<std::uint8_t>(frame[at]);
    if (byte <= '$' || byte >= 0x7F) return false;  // space, '!', '"', start bytes, control, non-ASCII
  }
  out.starts[count] = static_cast<std::uint8_t>(field_at);
  out.count = count;
  return true;
}

namespace {

// Any frame, with a message that names what is wrong with a bad one.
Result<FrameView> parse_any_frame(Bytes frame) {
  if (frame.empty()) return frame_error(Errc::truncated, "empty");
  if (frame.size() > max_frame_length) {
    return frame_error(Errc::overlong,
                       std::to_string(frame.size()) + " bytes, longer than " + std::to_string(max_frame_length));
  }
  FrameView view;
  const std::uint8_t start = frame[0];
  std::size_t body_offset = 1;
  if (start == '#') {
    if (frame.size() < 2) return frame_error(Errc::truncated, "'#' frame without an address byte");
    const std::uint8_t address = frame[1];
    if (address < first_unit_address) {
      return frame_error(Errc::invalid_frame, "address byte " + detail::hex_byte(address) + " below 0x30");
    }
    view.address = Address::unit(address);
    body_offset = 2;
  } else if (start != '$') {
    return frame_error(Errc::invalid_frame, "starts with " + detail::hex_byte(start) + ", not '$' or '#'");
  }
  if (auto parsed = parse_body(view, as_text(frame.subspan(body_offset)), body_offset); !parsed) {
    return std::move(parsed).error();
  }
  return view;
}

}  // namespace

Result<FrameView> parse_frame(Bytes frame) {
  // Returned by name on every path, so it is built in the caller's slot.
  Result<FrameView> parsed = FrameView{};
  if (detail::CommonFrame common; detail::parse_common_frame(as_text(frame), common)) {
    FrameView& view = *parsed;
    view.address = common.address;
    view.mnemonic = common.mnemonic();
    for (std::size_t i = 0; i < common.count; ++i) view.field_slots[i] = common[i];
    view.field_count = common.count;
  } else {
    parsed = parse_any_frame(frame);
  }
  return parsed;
}

Result<FrameView> parse_frame(std::string_view frame) { return parse_frame(as_bytes(frame)); }

Result<FrameView> parse_wire_frame(Bytes wire) {
  const FrameScan scan = scan_frame(wire);
  switch (scan.status) {
    case FrameStatus::need_more:
      if (wire.empty()) return frame_error(Errc::truncated, "no bytes");
      return frame_error(Errc::truncated,
                         "no CR terminator after " + std::to_string(wire.size()) + " bytes (truncated)");
    case FrameStatus::invalid: {
      if (scan.benign()) return frame_error(Errc::invalid_frame, "line ending before the start byte");
      const std::string_view reason = scan.reason;
      const Errc code = reason.find("longer") != std::string_view::npos ? Errc::overlong : Errc::invalid_frame;
      return frame_error(code, std::string(reason));
    }
    case FrameStatus::complete:
      break;
  }
  if (scan.consumed != wire.size()) {
    return frame_error(Errc::invalid_frame, std::to_string(wire.size() - scan.consumed) + " bytes after the CR");
  }
  return parse_frame(scan.frame);
}

}  // namespace rangekit::uls
