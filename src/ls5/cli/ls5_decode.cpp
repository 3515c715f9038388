// The LS5's option of `rangekit decode`: its measurement range, which turns result
// codes into millimetres (formula 8.1).
#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "ls5/cli/ls5_cli.hpp"
#include "rangekit/ls5/frame.hpp"
#include "rangekit/ls5/reply.hpp"
#include "rangekit/ls5/request.hpp"

namespace rangekit::cli {

DecoderFactory add_ls5_decode_options(CLI::App& decode) {
  auto range_mm = std::make_shared<double>(0);
  decode.add_option("--range-mm", *range_mm, "LS5 measurement range, to print millimetres")->check(range_millimetres());
  // The range, as given or as the sensor's identification reply says (formula 8.1 needs it),
  // shared by both sides' decoders: a tap reads the stream in millimetres once it heard ID.
  auto learned_range = std::make_shared<std::optional<double>>();
  return [range_mm, learned_range](Direction sender) {
    if (!*learned_range) *learned_range = *range_mm;
    return FrameDecoder{
        sender == Direction::to_device ? &ls5::scan_request_frame : &ls5::scan_reply_frame,
        [sender, learned_range](Bytes frame) {
          if (sender == Direction::from_device) {
            const auto reply = ls5::parse_reply(frame);
            if (reply && reply->kind == ls5::ReplyKind::identification && reply->identification.range_mm > 0) {
              *learned_range = reply->identification.range_mm;
            }
          }
          return describe_ls5_frame(frame, sender, learned_range->value_or(0));
        },
        [sender](Bytes frame) {
          // A result (FR, LR) or a stream record: a code the target made (§8).
          const auto reply = ls5::parse_reply(frame);
          return sender == Direction::from_device && reply.ok() &&
                 (reply->kind == ls5::ReplyKind::result || reply->kind == ls5::ReplyKind::stream_record);
        },
        [sender](Bytes frame) {
          return sender == Direction::to_device ? ls5::parse_request(frame).ok() : ls5::parse_reply(frame).ok();
        }};
  };
}

}  // namespace rangekit::cli
