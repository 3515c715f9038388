// The spike check: a distance that leaves the level of its stream and is back at the next
// reading is a corrupted value, whatever speed the target may have, since a target that
// moved would stay where it went. Neither protocol has a checksum; this catches a changed
// digit that the jump check (sample_quality.hpp) lets through because a target could move
// that far in one output period. It costs one output period of latency: each distance of a
// fast stream is held until the next reading of its sensor arrives (docs/reliability.md).
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "rangekit/core/sample.hpp"

namespace rangekit {

struct SpikeSettings {
  // Streams whose readings come further apart than this are not held, and not checked: the
  // wait for the next reading would cost more than a reading is worth late.
  std::chrono::milliseconds hold_limit{100};
};

class SpikeCheck {
 public:
  static constexpr std::size_t window = 101;      // readings the level is the median of
  static constexpr std::size_t min_level = 25;    // readings before anything is judged
  static constexpr std::size_t max_waiting = 64;  // line events held behind a reading

  explicit SpikeCheck(SpikeSettings settings = {}) : settings_(settings) {}

  // Takes each item in arrival order, `now` its arrival, and appends to `out`, oldest first,
  // what leaves now. A distance of a fast stream is held until the next reading of its sensor
  // judges it. An event about the line (a bad frame, lost records, a device error) waits
  // behind what is held (at most 64 of them); a link event (connected, disconnected,
  // reconnected, polling) first lets everything go, unjudged.
  void push(StreamItem item, std::chrono::steady_clock::time_point now, std::vector<StreamItem>& out);
  // Everything held, unjudged, oldest first: at the stream's end.
  void release_all(std::vector<StreamItem>& out);
  // What has waited longer than the hold limit (a stream that paused), unjudged.
  void release_due(std::chrono::steady_clock::time_point now, std::vector<StreamItem>& out);
  [[nodiscard]] bool holding() const noexcept { return held_count_ > 0; }

 private:
  struct Level {
    std::array<double, window> values{};
    std::size_t size = 0;
    std::size_t next = 0;
    // The readings' spread: an exponential mean of their distance from the level, over about
    // 128 readings (a spread taken from the window alone is too often far too small).
    double mean_deviation = 0;
    // The window's values in order, kept as each reading comes (a shift of at most 101
    // doubles): the median is read off, where sorting the window cost a microsecond a reading.
    std::array<double, window> sorted{};
    void push(double value);
    [[nodiscard]] double median() const;
  };
  // The distance a spike is judged on, and the sensor's stated accuracy and resolution there.
  struct Judged {
    double value_m = 0;
    double accuracy_m = 0;
    double resolution_m = 0;
  };
  struct Stream {
    Level level;
    std::optional<double> last;  // the newest reading released unflagged
    std::optional<Sample> held;
    Judged held_reading;               // what held is judged on, worked out once as it came
    std::vector<StreamEvent> waiting;  // line events that came after the held reading
    std::chrono::steady_clock::time_point held_at;
    std::uint64_t held_order = 0;
    std::optional<std::chrono::steady_clock::time_point> first_arrival;
    std::chrono::steady_clock::time_point last_arrival;
    std::uint64_t arrivals = 0;
  };
  using Key = std::tuple<std::string, SharedName, int>;

  void push_sample(Sample sample, std::chrono::steady_clock::time_point now, std::vector<StreamItem>& out);
  // Judged only where the sample itself shows its scale (an LS5 code 0 does not).
  static std::optional<Judged> judged(const Sample& sample);
  void judge(Stream& stream, Sample& held, const Sample& next, const std::optional<Judged>& next_reading) const;
  void release(Stream& stream, std::vector<StreamItem>& out);

  SpikeSettings settings_;
  std::map<Key, Stream> streams_;
  std::size_t held_count_ = 0;
  std::uint64_t order_ = 0;
};

}  // namespace rangekit
