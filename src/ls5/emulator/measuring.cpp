// The LS5 model's measurement pipeline (figure 8.7): the trigger by timer or sync input, the
// raw code from the scene, derivative, hold-over and pre-filter, then the stream and UDP.
#include "rangekit/ls5/emulator/firmware.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rangekit::ls5::emulator {
namespace {

constexpr double bright_exposure_us = 20;  // exposure a white target needs (scene reflectivity 1)

Nanos from_ms(double ms) { return Nanos(static_cast<std::int64_t>(std::llround(ms * 1e6))); }

}  // namespace

double Firmware::seconds_of(Nanos t) noexcept { return static_cast<double>(t.count()) / 1e9; }

std::optional<double> Firmware::raw_measurement(Nanos now, bool& weak) {
  const Scene& scene = config_.scene;
  weak = false;
  const double t = seconds_of(now);
  for (const auto& dropout : scene.dropouts) {
    if (t >= dropout.start_s && t < dropout.end_s) return std::nullopt;
  }
  if (scene.dust_probability > 0 && std::uniform_real_distribution<double>(0, 1)(random_) < scene.dust_probability) {
    return std::nullopt;
  }
  if (scene.reflectivity <= 0) return std::nullopt;
  // §8.5: the exposure a target needs grows as it reflects less.
  const double needed_us = bright_exposure_us / scene.reflectivity;
  const double period_us = static_cast<double>(period().count()) / 1000.0;
  double available_us = period_us;
  if (version_.at_least(firmware_7_0)) {
    const double max_exposure = static_cast<double>(u16(address::exposure_low));
    available_us = ram_[address::priority] == 0x01 ? max_exposure : std::min(max_exposure, period_us);
  }
  if (needed_us > available_us) return std::nullopt;
  weak = needed_us > period_us;
  double position = scene.target_set ? scene.target.position_at(now) : config_.lower_boundary_mm + config_.range_mm / 2;
  const double error = digital_error_limit_mm(config_.range_mm);  // §3: ±0.15 % of the range
  const double sigma = scene.noise_mm >= 0 ? scene.noise_mm : error / 3;
  if (sigma > 0) {
    const double noise = std::normal_distribution<double>(0, sigma)(random_);
    position += std::clamp(noise, -error, error);
  }
  return position - config_.lower_boundary_mm;
}

void Firmware::measure(Nanos now, bool from_sync) {
  last_measurement_ = now;
  ++measurements_;
  bool weak = false;
  const auto distance = raw_measurement(now, weak);
  std::optional<std::uint16_t> value;
  if (distance) {
    if (auto code = code_from_distance(*distance, config_.range_mm)) value = *code;  // outside the range: no signal
  }
  // Derivative (§8.8, L11, L30).
  if (version_.at_least(firmware_8_0) && ram_[address::result_type] == 0x01 && value) {
    const std::uint16_t raw = *value;
    value = previous_raw_ ? derivative_code(raw, *previous_raw_) : derivative_zero_code;
    previous_raw_ = raw;
  } else if (value) {
    previous_raw_ = value;
  }
  // τ (§8.6, L88): the last result stands in while at most τ has passed, so the default τ of
  // 10 ms bridges one lost measurement at the default 10 ms period.
  if (value) {
    last_valid_ = value;
    last_valid_at_ = now;
  } else if (last_valid_ && now - last_valid_at_ <= from_ms(u16(address::signal_absence_low))) {
    value = last_valid_;
  } else {
    previous_raw_.reset();  // a loss τ does not bridge: the derivative starts again (L89)
  }
  // Pre-filter (§8.7, L32).
  if (value) {
    const bool median = ram_[address::pre_filter] == 0x01;
    const std::size_t points = median ? ram_[address::median_points] : ram_[address::averaging_points];
    window_.push_back(*value);
    while (window_.size() > std::max<std::size_t>(1, points)) window_.pop_front();
    if (median) {
      std::vector<std::uint16_t> sorted(window_.begin(), window_.end());
      std::sort(sorted.begin(), sorted.end());
      value = sorted[sorted.size() / 2];
    } else {
      std::uint64_t sum = 0;
      for (const auto v : window_) sum += v;
      value = static_cast<std::uint16_t>((sum * 2 + window_.size()) / (2 * window_.size()));
    }
  } else {
    window_.clear();
  }
  current_ = classify_result_code(value ? *value : code_no_signal);
  measured_once_ = true;
  update_outputs();

  const bool sync_triggered = ram_[address::triggering] == 0x01;
  // Next cycle: the period, or longer while a weak target needs a long exposure (§8.5 sensitivity priority).
  if (!sync_triggered) {
    Nanos cycle = period();
    if (version_.at_least(firmware_7_0) && ram_[address::priority] == 0x01) {
      const double reflectivity = config_.scene.reflectivity;
      const double needed_us = reflectivity > 0 ? bright_exposure_us / reflectivity : 1e12;
      const double max_exposure = static_cast<double>(u16(address::exposure_low));
      const double used_us = std::min(needed_us, max_exposure);
      cycle = std::max(cycle, Nanos(static_cast<std::int64_t>(used_us * 1000)));
    }
    next_measurement_ = now + cycle;
  } else {
    next_measurement_ = Nanos::max();
  }
  (void)weak;

  const std::uint8_t n = std::max<std::uint8_t>(1, ram_[address::thinning]);
  // Stream (§8.4): every n-th result; none in the §8.13 case sync triggering + latching, and
  // with timer triggering a measurement the sync input started to latch is not streamed (L33).
  const bool latch_cycle = ram_[address::latching] != 0x00 && (sync_triggered || from_sync);
  if (streaming_ && !latch_cycle) {
    if (++thinning_count_ % n == 0) {
      if (pacer_.idle_at(now) <= now) {
        reply(Reply::stream_record(current_), now);
        ++records_sent_;
      } else {
        ++records_skipped_;  // the UART is still busy: the record is lost (§8.4)
      }
    }
  }
  if (model_.ethernet && ram_[address::udp_auto_stream] == 0x01 && measurements_ % n == 0) push_udp(current_);
}

void Firmware::set_sync_input(bool high, Nanos now) {
  advance(now);
  const bool rising = high && !sync_high_;
  sync_high_ = high;
  if (!rising || !on_ || phase_ != Phase::operating) return;
  const bool sync_triggered = ram_[address::triggering] == 0x01;
  if (ram_[address::latching] != 0) {
    // §8.13: the edge starts a measurement and latches it, whatever the sensor was doing.
    measure(now, true);
    latch(now);
    return;
  }
  if (!sync_triggered) return;
  // Edges faster than the measurement period are skipped (§8.13).
  if (last_measurement_ != Nanos::min() && now - last_measurement_ < period()) return;
  measure(now, true);
}

}  // namespace rangekit::ls5::emulator
