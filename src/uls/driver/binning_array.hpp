// Assembling one binning target array `BM,i,m,n,s` (U10), shared by a poll (driver.cpp)
// and the stream (stream.cpp): lines 0..m-1 in order make one list of targets.
#pragma once

#include <vector>

#include "rangekit/core/sample.hpp"
#include "rangekit/uls/measurement.hpp"

namespace rangekit::uls::detail {

enum class BinningArray { incomplete, complete, out_of_order };

// Adds one line to `targets`. Index 0 starts a new array; a line out of order drops what
// was collected. `complete` once the array's last line has arrived.
inline BinningArray collect_binning_target(std::vector<TargetHit>& targets, const BinningTarget& target) {
  if (target.index == 0) targets.clear();
  if (target.index != targets.size()) {
    targets.clear();
    return BinningArray::out_of_order;
  }
  targets.push_back(TargetHit{target.range.metres, target.strength});
  return targets.size() >= target.count ? BinningArray::complete : BinningArray::incomplete;
}

}  // namespace rangekit::uls::detail
