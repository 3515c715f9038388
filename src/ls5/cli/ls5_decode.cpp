// The LS5's option of `rangekit decode`: its measurement range, which turns result
// codes into millimetres (formula 8.1).
#include <memory>

#include "cli/commands.hpp"
#include "ls5/cli/ls5_cli.hpp"
#include "rangekit/ls5/frame.hpp"
#include "rangekit/ls5/reply.hpp"

namespace rangekit::cli {

DecoderFactory add_ls5_decode_options(CLI::App& decode) {
  auto range_mm = std::make_shared<double>(0);
  decode.add_option("--range-mm", *range_mm, "LS5 measurement range, to print millimetres")->check(range_millimetres());
  return [range_mm](Direction sender) {
    return FrameDecoder{
        sender == Direction::to_device ? &ls5::scan_request_frame : &ls5::scan_reply_frame,
        [sender, range = *range_mm](Bytes frame) { return describe_ls5_frame(frame, sender, range); },
        [sender](Bytes frame) {
          // A result (FR, LR) or a stream record: a code the target made (§8).
          const auto reply = ls5::parse_reply(frame);
          return sender == Direction::from_device && reply.ok() &&
                 (reply->kind == ls5::ReplyKind::result || reply->kind == ls5::ReplyKind::stream_record);
        }};
  };
}

}  // namespace rangekit::cli
