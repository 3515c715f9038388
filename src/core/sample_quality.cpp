#include "rangekit/core/sample_quality.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rangekit {
namespace {

template <class... Args>
std::string format_reason(const char* format, Args... args) {
  std::array<char, 160> text{};
  std::snprintf(text.data(), text.size(), format, args...);
  return text.data();
}

}  // namespace

void SampleChecker::History::push(Point point) {
  points[next] = point;
  next = (next + 1) % window;
  size = std::min(size + 1, window);
}

SampleChecker::Median SampleChecker::History::median() const {
  // Sort the points' slots by value; the median's age is that of its (older) middle point.
  std::array<std::size_t, window> slots{};
  for (std::size_t i = 0; i < size; ++i) slots[i] = i;
  // An insertion sort of at most `window` slots: std::sort here trips g++ 12's
  // -Warray-bounds (its 16-element insertion step) in the -O2 ThreadSanitizer build.
  for (std::size_t i = 1; i < size; ++i) {
    const std::size_t slot = slots[i];
    std::size_t at = i;
    for (; at > 0 && points[slot].value < points[slots[at - 1]].value; --at) slots[at] = slots[at - 1];
    slots[at] = slot;
  }
  // How many pushes ago a slot was written: 1 for the newest.
  const auto age = [this](std::size_t slot) { return (next + window - 1 - slot) % window + 1; };
  const std::size_t upper = slots[size / 2];
  if (size % 2 == 1) return {points[upper].value, points[upper].time, age(upper)};
  const std::size_t lower = slots[size / 2 - 1];
  const std::size_t older = age(lower) > age(upper) ? lower : upper;
  return {(points[lower].value + points[upper].value) / 2, points[older].time, age(older)};
}

double SampleChecker::Stream::period_s() const {
  if (!first_time || count < 2) return 0;
  return std::max(0.0, std::chrono::duration<double>(last_time - *first_time).count()) / static_cast<double>(count - 1);
}

void SampleChecker::check(Sample& sample) {
  const auto input = quality_input_of(sample);
  if (!input) return;  // a kind its family does not judge
  Stream& stream = streams_[Key{sample.device, sample.source, sample.address, sample.kind}];
  if (input->scale) stream.scale = input->scale;
  if (!stream.scale) return;  // the first records of a stream that shows no scale yet
  // Two honest readings of a still target may differ by twice the accuracy: the median and the
  // new reading may err in opposite directions.
  const double noise_m = 2 * stream.scale->accuracy_m;
  const double max_speed = settings_.max_speed_mps.value_or(stream.scale->max_speed_mps);
  const std::optional<double>& distance_m = input->distance_m;

  if (!stream.first_time) stream.first_time = sample.time;
  stream.last_time = sample.time;
  ++stream.count;
  if (distance_m && std::isfinite(*distance_m)) {
    History& history = stream.distance;
    // Until the receive times have moved at all (a first read handing over several
    // records), how far apart the readings are is unknown: nothing is judged.
    if (history.size >= min_history && stream.period_s() > 0) {
      // The median is one of the recent readings (the older middle one for an even count):
      // the target was within the noise of it then and has moved at most max_speed since.
      // Host receive times bunch up when a read returns several records, so the time
      // since is at least the mean receive interval so far times the readings since.
      const Median median_point = history.median();
      const double received_s = std::chrono::duration<double>(sample.time - median_point.time).count();
      const double span_s = std::max(received_s, stream.period_s() * static_cast<double>(median_point.age));
      const double median = median_point.value;
      const double allowed = noise_m + max_speed * span_s;
      if (std::abs(*distance_m - median) > allowed) {
        sample.suspect = true;
        sample.suspect_reason =
            format_reason("jump: %.4f m from the median %.4f m of the last readings; at most %.4f m in %.3f s",
                          *distance_m, median, allowed, span_s);
      }
    }
    history.push({*distance_m, sample.time});
  }

  if (input->pulse_width_ps) {
    History& history = stream.pulse_width;
    const double width = *input->pulse_width_ps;
    if (history.size >= min_history && !sample.suspect) {
      const double median = history.median().value;
      const double ratio = settings_.max_pulse_width_ratio;
      if (median > 0 && (width > median * ratio || width < median / ratio)) {
        sample.suspect = true;
        sample.suspect_reason = format_reason(
            "pulse width: %.0f ps against the median %.0f ps of the last readings "
            "(more than a factor %.1f)",
            width, median, ratio);
      }
    }
    history.push({width, sample.time});
  }
}

}  // namespace rangekit
