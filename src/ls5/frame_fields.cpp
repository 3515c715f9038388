#include "ls5/frame_fields.hpp"

#include <string>

#include "ls5/messages.hpp"
#include "rangekit/core/text.hpp"

namespace rangekit::ls5::detail {

Status check_printable(std::string_view frame) {
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const auto byte = static_cast<std::uint8_t>(frame[i]);
    if (byte < 0x20 || byte >= 0x7f) {
      return frame_error(Errc::invalid_frame, "control or non-ASCII byte 0x" + text::hex_byte(byte) + " at position " +
                                                  std::to_string(i) + " of " + quote(frame));
    }
  }
  return ok_status();
}

Result<std::uint8_t> parse_hex_byte(std::string_view frame, std::size_t at, const char* what) {
  const std::string_view digits = frame.substr(at, 2);
  const auto value = digits.size() == 2 ? text::parse_hex(digits, 2) : std::nullopt;
  if (!value) return frame_error(Errc::bad_hex, std::string(what) + " " + quote(digits) + " is not hex");
  return static_cast<std::uint8_t>(*value);
}

Result<std::uint8_t> parse_address(std::string_view frame) {
  if (frame.size() < 3) {
    return frame_error(Errc::truncated, quote(frame) + " ends before its two-digit network address");
  }
  return parse_hex_byte(frame, 1, "network address");
}

Result<const CommandInfo*> parse_command(std::string_view frame) {
  if (frame.size() < 4) return frame_error(Errc::truncated, quote(frame) + " ends before its command");
  const bool one_letter = frame[3] == 'R' || frame[3] == 'W';
  const std::string_view code = frame.substr(3, one_letter ? 1 : 2);
  if (code.size() < 2 && !one_letter) {
    return frame_error(Errc::truncated, "command " + quote(code) + " of " + quote(frame) + " is cut short");
  }
  if (const CommandInfo* command = find_command_by_code(code)) return command;
  // Name the mistake a terminal user makes most: lower-case mnemonics.
  const char upper_first = text::to_upper(code[0]);
  const bool upper_one_letter = upper_first == 'R' || upper_first == 'W';
  std::string upper(1, upper_first);
  if (!upper_one_letter && code.size() == 2) upper.push_back(text::to_upper(code[1]));
  if (find_command_by_code(upper) != nullptr) {
    return frame_error(Errc::unknown_command,
                       "command " + quote(frame.substr(3, upper.size())) + " must be upper case (" + upper + ")");
  }
  return frame_error(Errc::unknown_command,
                     "command " + quote(code) + " in " + quote(frame) + " is not an LS5 command (table 9.1)");
}

Status check_argument_length(std::string_view frame, const CommandInfo& command, std::size_t expected,
                             const char* what) {
  const std::size_t at = 3 + command.code.size();
  const std::string_view arguments = frame.substr(at);
  if (arguments.size() < expected) {
    return frame_error(Errc::truncated, std::string(command.code) + " takes " + what + " (" + std::to_string(expected) +
                                            " characters), got " + quote(arguments) + " in " + quote(frame));
  }
  if (arguments.size() > expected) {
    return frame_error(Errc::overlong, "unexpected " + quote(arguments.substr(expected)) + " after " +
                                           std::string(command.code) + " in " + quote(frame));
  }
  return ok_status();
}

void append_hex_byte(FrameText& out, std::uint8_t value) noexcept {
  char digits[2];
  text::write_hex(value, 2, digits);
  out.append(std::string_view(digits, 2));
}

void append_result_code(FrameText& out, std::uint16_t code) noexcept {
  char digits[5];
  unsigned rest = code;
  for (int i = 4; i >= 0; --i) {
    digits[i] = static_cast<char>('0' + rest % 10);
    rest /= 10;
  }
  out.append(std::string_view(digits, 5));
}

}  // namespace rangekit::ls5::detail
