// What goes on `<base>/<sensor>/reading`: each sample as `stream --format jsonl` writes it
// while the sensor stays under the configured rate; above it, one message per window of
// 1/rate seconds with the figures of the samples' readings (core/family.hpp) and the quality
// counts. A suspect sample is counted and kept out of the figures.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "rangekit/core/reading_stats.hpp"
#include "rangekit/core/sample.hpp"

namespace rangekit::mqtt {

class ReadingWindow {
 public:
  using Clock = std::chrono::steady_clock;
  explicit ReadingWindow(double max_rate_hz);

  // The message to publish now, if any.
  std::optional<std::string> add(const Sample& sample, Clock::time_point now);
  // Records lost on the way (a stream's lost_records event): counted in the next window.
  void add_lost(std::uint64_t count);
  // The pending window once its time is up.
  std::optional<std::string> flush_due(Clock::time_point now);

 private:
  std::optional<std::string> close_window(Clock::time_point now);

  Clock::duration period_{};  // zero: every sample
  std::optional<Clock::time_point> last_publish_;
  // The window being gathered.
  std::uint64_t count_ = 0;
  ReadingStats readings_;
  std::uint64_t no_signal_ = 0, lost_ = 0, errors_ = 0, suspect_ = 0;
  std::optional<bool> presence_;
  std::optional<Sample> single_;  // the window's first sample: its own message when it stays alone
  std::chrono::system_clock::time_point first_time_{}, last_time_{};
};

}  // namespace rangekit::mqtt
