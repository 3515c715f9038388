// Human-readable descriptions of decoded frames, shared by `decode` and `demo`.
#pragma once

#include <string>

#include "rangekit/core/framer.hpp"
#include "rangekit/ls5/reply.hpp"
#include "rangekit/uls/measurement.hpp"

namespace rangekit::cli {

enum class Direction { to_device, from_device };

// One ULS frame (without CR). From the device, BM lines are read with `context`.
std::string describe_uls_frame(Bytes frame, Direction direction, const uls::MeasurementContext& context);
// One LS5 frame (without CR); `range_mm` turns result codes into millimetres (0: codes only).
std::string describe_ls5_frame(Bytes frame, Direction direction, double range_mm);
// The frame as printable text: bytes outside ASCII shown as <xx>.
std::string printable(Bytes frame);

}  // namespace rangekit::cli
