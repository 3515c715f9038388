// The `targets` column of a capture (JSON text [{"distance_m": d, "strength": s}, ...]) read
// back into a TargetList; shared by the SQLite reader and the direct page reader.
#pragma once

#include <string_view>

#include "rangekit/core/sample.hpp"

namespace rangekit::record {

// Appends the targets of `text` to `targets`; entries that are not objects are skipped,
// text that is not a JSON array adds nothing.
void parse_targets_text(std::string_view text, TargetList& targets);

}  // namespace rangekit::record
