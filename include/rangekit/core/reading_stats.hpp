// The figures a window of readings is summed up by: how many, min, mean, max and last, and the
// channel they are of. A reading of another channel (the sensor changed mode) starts the
// figures afresh, so one window never mixes quantities or units.
#pragma once

#include <cstddef>

#include "rangekit/core/channel.hpp"

namespace rangekit {

class ReadingStats {
 public:
  void add(const Reading& reading) noexcept;
  void clear() noexcept { *this = ReadingStats{}; }

  [[nodiscard]] std::size_t count() const noexcept { return count_; }
  [[nodiscard]] bool empty() const noexcept { return count_ == 0; }
  // Null while empty.
  [[nodiscard]] const ChannelDescriptor* channel() const noexcept { return channel_; }
  [[nodiscard]] const char* unit() const noexcept;  // "" while empty
  // Rounded to the readings' decimals (the most any of them had).
  [[nodiscard]] double min() const noexcept { return rounded_to(min_, decimals_); }
  [[nodiscard]] double max() const noexcept { return rounded_to(max_, decimals_); }
  [[nodiscard]] double mean() const noexcept;
  [[nodiscard]] double last() const noexcept { return rounded_to(last_, decimals_); }

 private:
  const ChannelDescriptor* channel_ = nullptr;
  std::size_t count_ = 0;
  double min_ = 0;
  double max_ = 0;
  double sum_ = 0;
  double last_ = 0;
  int decimals_ = -1;
};

}  // namespace rangekit
