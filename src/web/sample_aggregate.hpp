// One sensor's samples merged for one event of an SSE stream with max_rate (docs/api.md):
// count, min, max and last. No reading is a gap; suspect samples are counted apart and
// kept out of min/max/last, so one corrupt record cannot stretch a plotted window.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>

#include "rangekit/core/reading_stats.hpp"
#include "rangekit/core/sample.hpp"

namespace rangekit::web {

class SampleAggregate {
 public:
  void add(const Sample& sample, std::uint64_t id);
  bool empty() const { return count_ == 0; }
  // Appends the `event: aggregate` block and starts an empty merge.
  void append_event(std::string& out, std::string_view sensor);

 private:
  std::uint64_t last_id_ = 0;
  std::size_t count_ = 0;    // samples merged
  std::size_t gaps_ = 0;     // of which with no reading
  std::size_t suspect_ = 0;  // of which marked suspect (not in min/max/last)
  ReadingStats readings_;    // the others
  std::chrono::system_clock::time_point time_;
};

}  // namespace rangekit::web
