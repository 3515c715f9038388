// Bounded diagnostics (docs/reliability.md), so a babbling line cannot flood stderr: the
// first event of a kind is printed, repeats are merged into one summary a second per kind.
// Only the printing is merged: the events still reach the output, capture and counts.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "rangekit/core/sample.hpp"

namespace rangekit::record {

class DiagnosticLimiter {
 public:
  using TimePoint = std::chrono::steady_clock::time_point;

  explicit DiagnosticLimiter(std::chrono::milliseconds window = std::chrono::seconds(1)) : window_(window) {}

  // Lines to print (each ending in '\n') for `event` seen at `now`: summaries of
  // windows that ended by then, and the event's own text when it is the first of
  // its kind since its kind was last quiet for a whole window.
  std::vector<std::string> on_event(const StreamEvent& event, TimePoint now);
  // Summaries of windows that ended by `now`; call it now and then (the status tick)
  // so a summary appears even when the events stop.
  std::vector<std::string> tick(TimePoint now);
  // Summaries of everything counted and not yet said, at the end of the stream.
  std::vector<std::string> finish(TimePoint now);

  // Events counted and not printed, over the whole run.
  [[nodiscard]] std::uint64_t merged() const noexcept { return merged_; }

 private:
  struct KindState {
    bool open = false;  // an event of this kind was printed or summarised less than a window ago
    TimePoint since{};
    std::uint64_t unprinted = 0;
  };
  static constexpr std::size_t kind_count = 7;  // StreamEventKind's values
  void summarise(std::size_t kind, TimePoint now, std::vector<std::string>& lines);

  std::chrono::milliseconds window_;
  std::array<KindState, kind_count> kinds_{};
  std::uint64_t merged_ = 0;
};

// "412 more bad frames in the last 1 s"
std::string merged_events_text(StreamEventKind kind, std::uint64_t count, double seconds);

}  // namespace rangekit::record
