// The ULS as generic code sees it: its channels and the reading of each kind of sample.
#pragma once

#include "rangekit/core/family.hpp"

namespace rangekit::uls {

const FamilyDescriptor& family() noexcept;

}  // namespace rangekit::uls
