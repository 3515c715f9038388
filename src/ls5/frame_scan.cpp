#include "rangekit/ls5/frame.hpp"

namespace rangekit::ls5 {
namespace {

// Addresses are hex text, so no byte position needs the ULS address exception.
constexpr LineFramerRules request_rules{"#", '\r', max_frame_length, false, 0};
constexpr LineFramerRules reply_rules{"!%", '\r', max_frame_length, false, 0};

}  // namespace

FrameScan scan_request_frame(Bytes buffer) noexcept { return scan_line_frame(buffer, request_rules); }

FrameScan scan_reply_frame(Bytes buffer) noexcept { return scan_line_frame(buffer, reply_rules); }

}  // namespace rangekit::ls5
