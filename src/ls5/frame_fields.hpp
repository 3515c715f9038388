// Field readers and writers shared by the request and reply codecs.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "rangekit/core/framer.hpp"
#include "rangekit/core/result.hpp"
#include "rangekit/ls5/commands.hpp"
#include "rangekit/ls5/frame.hpp"

namespace rangekit::ls5::detail {

// Every byte printable ASCII; the error names the first one that is not.
Status check_printable(std::string_view frame);
// Two hex digits, either case (L3). `what` names the field in the error.
Result<std::uint8_t> parse_hex_byte(std::string_view frame, std::size_t at, const char* what);
// The two-digit address after the start character.
Result<std::uint8_t> parse_address(std::string_view frame);
// The command code at position 3: one letter (R, W) or two, upper case (L16).
Result<const CommandInfo*> parse_command(std::string_view frame);
// Exactly `expected` characters after the command, else truncated/overlong.
Status check_argument_length(std::string_view frame, const CommandInfo& command, std::size_t expected,
                             const char* what);

// Encoder helpers: append to a frame under construction.
void append_hex_byte(FrameText& out, std::uint8_t value) noexcept;
void append_result_code(FrameText& out, std::uint16_t code) noexcept;

// A CommandId inside the command table (an id cast from a number may not be).
inline bool valid_command(CommandId id) noexcept { return static_cast<std::size_t>(id) < command_count; }

}  // namespace rangekit::ls5::detail
