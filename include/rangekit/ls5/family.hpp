// The LS5 as generic code sees it: its channels and the reading of each kind of sample.
#pragma once

#include <optional>

#include "rangekit/core/family.hpp"

namespace rangekit::ls5 {

const FamilyDescriptor& family() noexcept;

// The sensor's range from a result: formula 8.1 (distance = code / 50000 × range) read
// backwards; none when the sample carries no distance or its code is 0.
std::optional<double> range_from_result_mm(const Sample& sample) noexcept;

}  // namespace rangekit::ls5
