// LS5 serial framing (§9.2, conformance F1-F5): requests start with '#', replies
// with '!' (or '%' for identification); every frame ends with CR.
#pragma once

#include <cstdint>

#include "rangekit/core/framer.hpp"
#include "rangekit/ls5/fixed_text.hpp"

namespace rangekit::ls5 {

inline constexpr char request_start = '#';
inline constexpr char reply_start = '!';
inline constexpr char identification_start = '%';
inline constexpr char frame_terminator = '\r';
inline constexpr std::size_t max_frame_length = 64;      // before the CR (F5)
inline constexpr std::uint8_t broadcast_address = 0x00;  // §8.1, L3

// Host -> sensor: frames starting with '#'.
FrameScan scan_request_frame(Bytes buffer) noexcept;
// Sensor -> host: frames starting with '!' or '%'.
FrameScan scan_reply_frame(Bytes buffer) noexcept;

// An encoded frame, terminator included.
using FrameText = FixedText<max_frame_length + 1>;

}  // namespace rangekit::ls5
