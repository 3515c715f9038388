#include "rangekit/ls5/frame.hpp"

namespace rangekit::ls5 {
namespace {

// Addresses are hex text, so no byte position needs the ULS address exception.
constexpr LineFramerRules request_rules{"#", '\r', max_frame_length, false, 0};
constexpr LineFramerRules reply_rules{"!%", '\r', max_frame_length, false, 0};

}  // namespace

FrameScan scan_request_frame(Bytes buffer) noexcept { return scan_line_frame(buffer, request_rules); }

FrameScan scan_reply_frame(Bytes buffer) noexcept {
  // A stream record "!ddddd<CR>" (L1), what a streaming LS5 sends most: the same
  // answer scan_line_frame gives, without its general checks, faster.
  if (buffer.size() >= 7 && buffer[0] == reply_start && buffer[6] == frame_terminator) {
    bool digits = true;
    for (std::size_t i = 1; i < 6; ++i) digits = digits && buffer[i] >= '0' && buffer[i] <= '9';
    if (digits) return FrameScan::complete(buffer.first(6), 7);
  }
  return scan_line_frame(buffer, reply_rules);
}

}  // namespace rangekit::ls5
