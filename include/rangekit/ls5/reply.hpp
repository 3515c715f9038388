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
// Writes the reply with its CR.
Result<FrameText> encode_reply(const Reply& reply);

// Whether `reply` answers `request`: same address, command and parameter, the
// written value echoed, the right form. For the driver.
Status check_reply_answers(const Request& request, const Reply& reply);

}  // namespace rangekit::ls5
