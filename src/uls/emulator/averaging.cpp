// Averaging mode (§3, §8 MM 1): timed, dithered returns, the noise filter and the mean.
#include "rangekit/uls/emulator/firmware.hpp"

#include <algorithm>
#include <cmath>

#include "uls/emulator/pulse_model.hpp"

namespace rangekit::uls::emulator {

void Firmware::fire_averaging(Nanos t) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double min_width_ps = settings_.min_pulse_width_ns * 1000.0;
  // Dust near the unit answers first; a minimum pulse width above its width rejects it (U41).
  const bool dust = scene_.dust > 0 && uniform(random_) < scene_.dust && dust_width_ns * 1000.0 >= min_width_ps;
  if (dust) {
    any_return_ = true;  // a weak return the noise filter rejects: a bad pulse
  } else if (auto hit = first_return(t, false, min_width_ps)) {
    any_return_ = true;
    const double sigma = hit->cooperative ? cooperative_jitter_m : jitter_m;
    double raw = hit->distance_m + sigma * normal_(random_);
    // The pulse is timed in quanta; dithering shifts the quantum grid over a 32-pulse cycle.
    const double shift = settings_.dither
                             ? (static_cast<double>(returns_m_.size() % dither_cycle) + 0.5) / dither_cycle * quantum_m
                             : 0.0;
    raw = std::round((raw + shift) / quantum_m) * quantum_m - shift;
    returns_m_.push_back(raw);
    returns_width_ps_.push_back(hit->width_ps);
  }
  if (++cycle_pulses_ >= settings_.ppm[0]) complete_averaging(t);
}

double Firmware::noise_filter_centre(double& window) {
  // "Averaging with Noise Filtering" (§8 MM 1, U48): the median return is the target;
  // returns farther from it than max(0.5 m, 6 x the median absolute deviation) are noise
  // (a missed near target answered by one behind it). A moving target spreads its returns
  // evenly, so the window grows with its travel and none of them is dropped.
  scratch_.assign(returns_m_.begin(), returns_m_.end());
  const auto middle = scratch_.begin() + static_cast<std::ptrdiff_t>(scratch_.size() / 2);
  std::nth_element(scratch_.begin(), middle, scratch_.end());
  const double centre = *middle;
  for (auto& value : scratch_) value = std::abs(value - centre);
  std::nth_element(scratch_.begin(), middle, scratch_.end());
  window = std::max(noise_window_m, 6.0 * *middle);
  return centre;
}

void Firmware::complete_averaging(Nanos t) {
  ++measurements_;
  double sum_m = 0;
  double width_sum_ps = 0;
  std::uint32_t good = 0;
  if (!returns_m_.empty()) {
    double window = 0;
    const double centre = noise_filter_centre(window);
    for (std::size_t i = 0; i < returns_m_.size() && good < settings_.averaging_weight; ++i) {
      if (std::abs(returns_m_[i] - centre) > window) continue;
      sum_m += returns_m_[i];
      width_sum_ps += returns_width_ps_[i];
      ++good;
    }
  }
  if (!any_return_) {
    record_error(4, t);
    emit({MeasurementError{4}}, t);
  } else if (good < settings_.averaging_weight) {
    record_error(5, t);
    emit({MeasurementError{5}}, t);
  } else {
    const double metres = sum_m / good + settings_.offset_m;
    record_distance(metres, t);
    AveragingReading reading;
    const auto width = static_cast<std::uint32_t>(std::clamp(std::round(width_sum_ps / good), 0.0, 9'999'999.0));
    if (settings_.display != DisplayMode::intensity) {
      const double user = from_metres(metres, settings_.units);
      reading.range =
          make_range(settings_.units == Units::metres ? std::round(user * 1000) / 1000 : std::round(user * 100) / 100,
                     settings_.units);
    }
    if (settings_.display != DisplayMode::range) reading.pulse_width_ps = width;
    emit({reading}, t);
  }
  reset_cycle();
}

}  // namespace rangekit::uls::emulator
