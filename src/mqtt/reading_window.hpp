// What goes on `<base>/<sensor>/reading`: each sample as `stream --format jsonl`
// writes it while the sensor stays under the configured rate; above it, one message
// per window of 1/rate seconds with count, min, mean, max and last of the distances
// plus the quality counts. A sample without a distance (LS5 no signal, ULS $ER) is
// counted, never published as a distance; a suspect one (issue 18) is counted and kept
// out of min/mean/max/last, so one corrupt record cannot move a window's figures.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "rangekit/core/sample.hpp"

namespace rangekit::mqtt {

// The distance a sample carries and its unit, if any: ULS averaging and binning (nearest
// target) in metres, LS5 results in millimetres.
struct Distance {
  double value = 0;
  const char* unit = "m";
};
std::optional<Distance> distance_of(const Sample& sample);

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
  std::uint64_t distances_ = 0;
  double min_ = 0, max_ = 0, sum_ = 0, last_ = 0;
  const char* unit_ = "m";
  std::uint64_t no_signal_ = 0, lost_ = 0, errors_ = 0, suspect_ = 0;
  std::optional<bool> presence_;
  std::string single_;  // the only sample's own message, when the window holds one
  std::chrono::system_clock::time_point first_time_{}, last_time_{};
};

}  // namespace rangekit::mqtt
