// Replies sensor -> host (table 9.1): echoes "!AAON", parameter values "!AARaadd",
// results "!AAFRddddd", identification "%AA" + 35 characters, and stream
// records "!ddddd" (conformance L1, L2).
#pragma once

#include <cstdint>

#include "rangekit/core/framer.hpp"
#include "rangekit/core/result.hpp"
#include "rangekit/ls5/commands.hpp"
#include "rangekit/ls5/frame.hpp"
#include "rangekit/ls5/identification.hpp"
#include "rangekit/ls5/request.hpp"
#include "rangekit/ls5/result_code.hpp"

namespace rangekit::ls5 {

enum class ReplyKind : std::uint8_t {
  echo,             // !AA<cmd>[args]: FL ON OF FX SB DF, and W with its address and value
  parameter_value,  // !AARaadd
  result,           // !AAFRddddd, !AALRddddd
  identification,   // %AA + 35 characters
  stream_record,    // !ddddd, no address
};

struct Reply {
  ReplyKind kind = ReplyKind::echo;
  std::uint8_t address = 0x01;             // not used by stream records
  CommandId command = CommandId::turn_on;  // not used by stream records
  std::uint8_t parameter = 0;              // R, W
  std::uint8_t value = 0;                  // R, W
  ResultCode result{};                     // result, stream_record
  Identification identification{};         // identification

  static Reply echo(const Request& request) noexcept;
  static Reply parameter_value(std::uint8_t address, std::uint8_t parameter, std::uint8_t value) noexcept;
  static Reply result_of(std::uint8_t address, CommandId command, ResultCode code) noexcept;
  static Reply identification_of(std::uint8_t address, const Identification& identification) noexcept;
  static Reply stream_record(ResultCode code) noexcept;
};

// Parses a frame as scan_reply_frame hands it out: '!' or '%' up to, not including, CR.
Result<Reply> parse_reply(Bytes frame);
// Parses exactly one frame with its CR and nothing around it.
Result<Reply> parse_reply_line(Bytes line);

namespace detail {

inline constexpr std::size_t stream_record_length = 6;  // "!ddddd" (L1), without the CR

// The frame parse_reply reads as a stream record with a valid code (L1, L7): '!' and
// five digits of 0-50000, 65534 or 65535. True with the code; false for anything
// else, which parse_reply reads (or refuses, naming the problem) in full.
inline bool read_good_stream_record(const std::uint8_t* frame, std::uint16_t& code) noexcept {
  if (frame[0] != reply_start) return false;
  std::uint32_t value = 0;
  bool digits = true;
  for (std::size_t i = 1; i < stream_record_length; ++i) {
    const auto digit = static_cast<std::uint32_t>(frame[i] - '0');
    digits = digits && digit <= 9;
    value = value * 10 + digit;
  }
  if (!digits || (value > max_result_code && value != code_no_measurement_yet && value != code_no_signal)) {
    return false;
  }
  code = static_cast<std::uint16_t>(value);
  return true;
}

}  // namespace detail

// Hands out every frame `assembler` holds, in order, as the stream reader needs them:
// a stream record "!ddddd<CR>" with a valid code to on_record(ResultCode), read
// straight from the assembler's buffer with no Reply or Result built; any
// other frame to on_reply(Bytes frame, Result<Reply>) exactly as parse_reply reads it; rejected
// bytes to on_rejected(const FrameAssembler::Event&). The same calls, in the same
// order, as next() and parse_reply on every frame: scan_reply_frame hands out
// "!ddddd" before a CR as that frame, whatever follows.
template <class OnRecord, class OnReply, class OnRejected>
void decode_replies(FrameAssembler& assembler, OnRecord&& on_record, OnReply&& on_reply, OnRejected&& on_rejected) {
  constexpr std::size_t line_length = detail::stream_record_length + 1;
  FrameAssembler::Event event;
  while (true) {
    const Bytes pending = assembler.pending();
    const std::uint8_t* at = pending.data();
    const std::uint8_t* const end = at + pending.size();
    std::uint16_t code = 0;
    while (end - at >= static_cast<std::ptrdiff_t>(line_length) &&
           at[detail::stream_record_length] == frame_terminator && detail::read_good_stream_record(at, code)) {
      on_record(classify_result_code(code));
      at += line_length;
    }
    assembler.consume(static_cast<std::size_t>(at - pending.data()));
    if (!assembler.next(event)) return;
    if (event.kind == FrameAssembler::Event::Kind::rejected) {
      on_rejected(event);
    } else {
      on_reply(event.frame, parse_reply(event.frame));
    }
  }
}
// Writes the reply with its CR.
Result<FrameText> encode_reply(const Reply& reply);

// Whether `reply` answers `request`: same address, command and parameter, the
// written value echoed, the right form. For the driver.
Status check_reply_answers(const Request& request, const Reply& reply);

}  // namespace rangekit::ls5
