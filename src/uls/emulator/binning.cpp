// Binning mode (§3, §8 MM 2): hits counted in range bins, up to 15 targets a burst.
#include "rangekit/uls/emulator/firmware.hpp"

#include <algorithm>
#include <cmath>

#include "uls/emulator/pulse_model.hpp"

namespace rangekit::uls::emulator {

void Firmware::fire_binning(Nanos t) {
  const BinSize size = to_bin_size(settings_.bin_size).value_or(BinSize::inch_1);
  const double bin_m = bin_size_m(size);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  bool crossed = false;
  auto hit_at = [&](double d) {
    if (d < 0) return;
    const auto index = static_cast<std::size_t>(d / bin_m);
    if (index >= bins_.size()) return;
    const std::uint32_t hits = ++bins_[index];
    max_bin_ = std::max(max_bin_, hits);
    crossed = crossed || hits == settings_.bin_hits;
  };
  if (!fault_no_return_) {
    for (const auto& target : scene_.targets) {
      const double d = target.motion.position_at(t);
      if (!passes_gates(settings_, d, target.cooperative)) continue;
      // No threshold in binning (§3): weak returns still land, with a probability
      // falling with the signal strength (range / distance)^2, §9's binning range at its edge.
      const double ratio = binning_range_m(target.reflectivity, target.cooperative) / d;
      const double p = std::min(detect_probability, binning_edge_probability * ratio * ratio);
      if (uniform(random_) >= p) continue;
      std::normal_distribution<double> noise(0.0, target.cooperative ? cooperative_jitter_m : jitter_m);
      hit_at(d + noise(random_));
    }
    const double span = bin_m * static_cast<double>(bins_.size());
    double noise_hits = scene_.ambient_noise;
    while (noise_hits > 0) {
      if (noise_hits >= 1 || uniform(random_) < noise_hits) hit_at(uniform(random_) * span);
      noise_hits -= 1;
    }
    if (scene_.dust > 0 && uniform(random_) < scene_.dust) hit_at(minimum_range_m + uniform(random_) * 30.0);
  }
  ++cycle_pulses_;
  if (crossed) {
    // §3: "If 15 targets appear during binning, the unit restarts the firing sequence and
    // will not find targets beyond the last one detected" (U42): the burst ends here.
    bin_targets_ = count_bin_targets();
    if (bin_targets_ >= restart_targets) {
      ++restarts_;
      complete_binning(t);
      return;
    }
  }
  if (cycle_pulses_ >= settings_.ppm[1]) complete_binning(t);
}

std::size_t Firmware::count_bin_targets() const noexcept {
  std::size_t runs = 0;
  bool in_run = false;
  for (const auto hits : bins_) {
    const bool over = hits >= settings_.bin_hits;
    if (over && !in_run) ++runs;
    in_run = over;
  }
  return runs;
}

void Firmware::complete_binning(Nanos t) {
  ++measurements_;
  const BinSize size = to_bin_size(settings_.bin_size).value_or(BinSize::inch_1);
  const double bin_m = bin_size_m(size);
  struct Found {
    std::size_t bin;
    std::uint32_t hits;
  };
  std::vector<Found> found;
  for (std::size_t i = 0; i < bins_.size() && found.size() < max_binning_targets; ++i) {
    if (bins_[i] < settings_.bin_hits) continue;
    // A run of neighbouring bins over the threshold is one target, at its strongest bin (U38).
    Found best{i, bins_[i]};
    while (i + 1 < bins_.size() && bins_[i + 1] >= settings_.bin_hits) {
      ++i;
      if (bins_[i] > best.hits) best = {i, bins_[i]};
    }
    found.push_back(best);  // 15 targets: the unit restarts and sees nothing beyond (§3)
  }
  if (found.empty()) {
    record_error(4, t);
    emit({MeasurementError{4}}, t);
  } else {
    std::vector<Reading> lines;
    for (std::size_t i = 0; i < found.size(); ++i) {
      const double metres = (static_cast<double>(found[i].bin) + 0.5) * bin_m + settings_.offset_m;
      if (i == 0) record_distance(metres, t);
      const double user = from_metres(metres, settings_.units);
      BinningTarget target;
      target.index = static_cast<std::uint8_t>(i);
      target.count = static_cast<std::uint8_t>(found.size());
      target.range =
          make_range(settings_.units == Units::metres ? std::round(user * 1000) / 1000 : std::round(user * 100) / 100,
                     settings_.units);
      target.strength = std::min<std::uint32_t>(found[i].hits, 65535);
      lines.emplace_back(target);
    }
    emit(lines, t);
  }
  reset_cycle();
}
std::uint64_t Firmware::pulses_before_restart() const noexcept {
  // A pulse adds at most one hit per target, one per (rounded-up) noise hit and one of
  // dust, so the 15th target of U42 cannot appear sooner than this many pulses from now.
  const auto per_pulse = static_cast<std::uint64_t>(scene_.targets.size()) +
                         static_cast<std::uint64_t>(std::ceil(scene_.ambient_noise)) + 1;
  auto pulses_for = [per_pulse](std::uint64_t hits) {
    return std::max<std::uint64_t>(1, (hits + per_pulse - 1) / per_pulse);
  };
  std::uint64_t pulses = pulses_for(restart_targets - std::min(bin_targets_, restart_targets));
  if (max_bin_ < settings_.bin_hits) pulses = std::max(pulses, pulses_for(settings_.bin_hits - max_bin_));
  return pulses;
}

}  // namespace rangekit::uls::emulator
