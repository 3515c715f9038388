// Per-sample quality (docs/reliability.md, U101-U103, L71): a well-formed value judged
// against the recent ones, since neither protocol has a checksum. A sample that fails
// keeps its value and is marked suspect with the reason.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <tuple>

#include "rangekit/core/family.hpp"
#include "rangekit/core/sample.hpp"

namespace rangekit {

struct QualitySettings {
  // Fastest a real target moves along the beam, m/s; nullopt = the family's (DistanceScale).
  std::optional<double> max_speed_mps;
  // A pulse width further than this factor from the median of the recent ones is suspect.
  double max_pulse_width_ratio = 2.0;
};

class SampleChecker {
 public:
  static constexpr std::size_t window = 5;  // samples in the running median
  static constexpr std::size_t min_history = 3;

  explicit SampleChecker(QualitySettings settings = {}) : settings_(settings) {}

  // Marks `sample` suspect (suspect, suspect_reason) when a check fails; keeps its value.
  // Every distance joins the history, suspect or not, so a real step (a new target)
  // moves the median after min_history samples and flags at most a few.
  void check(Sample& sample);

 private:
  struct Point {
    double value = 0;
    std::chrono::system_clock::time_point time;
  };
  struct Median {
    double value = 0;
    std::chrono::system_clock::time_point time;  // of the reading it is (the older middle one)
    std::size_t age = 0;                         // readings since it, 1 = the newest
  };
  struct History {
    std::array<Point, window> points{};
    std::size_t size = 0;
    std::size_t next = 0;
    void push(Point point);
    [[nodiscard]] Median median() const;
  };
  struct Stream {
    History distance;
    History pulse_width;
    std::optional<DistanceScale> scale;  // from the last sample that showed it
    // The mean receive interval so far, for when a read hands over several records at once.
    std::optional<std::chrono::system_clock::time_point> first_time;
    std::chrono::system_clock::time_point last_time;
    std::uint64_t count = 0;
    [[nodiscard]] double period_s() const;
  };
  using Key = std::tuple<std::string, SharedName, int, SampleKind>;

  QualitySettings settings_;
  std::map<Key, Stream> streams_;
};

}  // namespace rangekit
