// Several sample sources as one (a ULS and an LS5 streaming into one capture):
// each source is read on its own thread, items come out in the order they
// arrived, and the merged source is finished when every source is.
#pragma once

#include <vector>

#include "rangekit/core/sample.hpp"

namespace rangekit::record {

// stop() stops every source; lost() adds up their losses (and the merge queue's).
SampleSourcePtr merge_sources(std::vector<SampleSourcePtr> sources);

}  // namespace rangekit::record
