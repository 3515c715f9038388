// Human-readable descriptions of decoded frames, shared by `decode` and `demo`; each family
// describes its own frames (cli_family.hpp).
#pragma once

#include <string>

#include "rangekit/core/framer.hpp"

namespace rangekit::cli {

enum class Direction { to_device, from_device };

// The frame as printable text: bytes outside ASCII shown as <xx>.
std::string printable(Bytes frame);

}  // namespace rangekit::cli
