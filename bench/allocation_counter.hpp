// Counts heap allocations made by this process (the bench binary replaces the
// global operator new), so a benchmark can report allocations per frame.
#pragma once

#include <cstdint>

namespace rangekit::bench {
std::uint64_t allocation_count() noexcept;
}  // namespace rangekit::bench
