#include "rangekit/core/reading_stats.hpp"

#include <algorithm>

namespace rangekit {

void ReadingStats::add(const Reading& reading) noexcept {
  if (reading.channel != channel_) {
    clear();
    channel_ = reading.channel;
  }
  min_ = count_ == 0 ? reading.value : std::min(min_, reading.value);
  max_ = count_ == 0 ? reading.value : std::max(max_, reading.value);
  sum_ += reading.value;
  last_ = reading.value;
  // Unknown decimals anywhere leave the figures unrounded.
  decimals_ = count_ == 0 ? reading.decimals
                          : (decimals_ < 0 || reading.decimals < 0 ? -1 : std::max(decimals_, reading.decimals));
  ++count_;
}

const char* ReadingStats::unit() const noexcept { return channel_ != nullptr ? unit_symbol(channel_->unit) : ""; }

double ReadingStats::mean() const noexcept {
  return count_ == 0 ? 0.0 : rounded_to(sum_ / static_cast<double>(count_), decimals_);
}

}  // namespace rangekit
