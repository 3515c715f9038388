// The ULS model's measuring: runs of pulses on the PRF's clock, the scene's returns, and the
// readings each completed measurement sends.
#include "rangekit/uls/emulator/firmware.hpp"

#include <algorithm>
#include <cmath>

#include "uls/emulator/pulse_model.hpp"

namespace rangekit::uls::emulator {

std::uint32_t Firmware::current_prf() const noexcept {
  return settings_.prf[static_cast<std::size_t>(wire_value(settings_.mode) - 1)];
}

std::uint32_t Firmware::current_ppm() const noexcept {
  return settings_.mode == Mode::binning ? settings_.ppm[1] : settings_.ppm[0];
}

Nanos Firmware::pulse_time(std::uint64_t index) const noexcept {
  // From a pulse counter, never by adding rounded periods: no drift over long runs.
  const std::uint64_t whole = index / run_prf_;
  const std::uint64_t part = index % run_prf_;
  return run_start_ + Nanos(static_cast<std::int64_t>(whole * 1'000'000'000ULL + part * 1'000'000'000ULL / run_prf_));
}

void Firmware::reset_cycle() {
  cycle_pulses_ = 0;
  any_return_ = false;
  returns_m_.clear();
  returns_width_ps_.clear();
  bins_.fill(0);
  max_bin_ = 0;
  bin_targets_ = 0;
}

void Firmware::start_measuring(Nanos now) {
  measuring_ = true;
  run_start_ = now;
  run_prf_ = current_prf();
  next_pulse_ = 1;  // the first pulse fires one period after the start
  reset_cycle();
  latest_.clear();
  reference_m_.reset();
  reference_pulses_ = 0;
  reference_candidate_m_ = 0;
  present_ = false;
  presence_tbe_ = TimeBetweenEvents{};
  disagreeing_ = 0;
  have_no_presence_edge_ = false;
  stable_pulses_ = 0;
  longer_pulses_ = 0;
  error_since_.reset();
  last_distance_m_.reset();  // the loop holds only a distance of this run (U81)
}

void Firmware::stop_measuring() {
  measuring_ = false;
  polls_.clear();
}

void Firmware::advance(Nanos now) {
  if (now < last_now_) now = last_now_;
  last_now_ = now;
  while (measuring_) {
    const Nanos t = pulse_time(next_pulse_);
    if (t > now) break;
    fire_pulse(t);
    ++next_pulse_;
  }
  for (auto& port : ports_) drain(port, now);
}

Nanos Firmware::next_deadline() const { return earliest_event(false); }

Nanos Firmware::next_wake() const { return earliest_event(true); }

Nanos Firmware::earliest_event(bool whole_runs) const {
  Nanos earliest = Nanos::max();
  for (const auto& port : ports_) {
    const Nanos output =
        whole_runs && port.pacer.queued() > 0 ? port.pacer.idle_at(last_now_) : port.pacer.next_completion();
    earliest = std::min(earliest, output);
    if (port.pending_baud) {
      const bool other_port = port.pending_port != static_cast<std::size_t>(&port - ports_.data());
      const Nanos idle = other_port ? port.pending_at : port.pacer.idle_at(last_now_);
      earliest = std::min(earliest, std::max({port.pending_at, idle, last_now_}) + Nanos(1));
    }
  }
  if (measuring_) {
    if (settings_.mode == Mode::look_down) {
      earliest = std::min(earliest, pulse_time(next_pulse_));
    } else {
      const std::uint32_t ppm = current_ppm();
      std::uint64_t remaining = ppm > cycle_pulses_ ? ppm - cycle_pulses_ - 1 : 0;
      if (settings_.mode == Mode::binning) remaining = std::min(remaining, pulses_before_restart() - 1);
      earliest = std::min(earliest, pulse_time(next_pulse_ + remaining));
    }
  }
  return earliest;
}

double Firmware::modelled_width_ps(double strength) {
  // The log is the costliest step of a pulse; a fixed target gives the same strength
  // every pulse, so the last answer is kept.
  if (strength != width_cache_strength_) {
    width_cache_strength_ = strength;
    width_cache_ps_ = (weakest_width_ns + width_ns_per_doubling * std::log2(1.0 + strength)) * 1000.0;
  }
  return width_cache_ps_;
}

double Firmware::max_range_m(double reflectivity, bool cooperative) const noexcept {
  const auto level = static_cast<std::size_t>(wire_value(settings_.power));
  if (cooperative) return cooperative_range_m;  // §9: 1700 m in all three power columns (U75)
  // §9 ranges at 90% and 20%, linear in reflectivity between and beyond them.
  const double r = std::clamp(reflectivity, 0.0, 1.0);
  const double range = gray_range_m[level] + (white_range_m[level] - gray_range_m[level]) * (r - 0.2) / 0.7;
  return std::max(range, 1.0);
}

double Firmware::binning_range_m(double reflectivity, bool cooperative) const noexcept {
  const auto level = static_cast<std::size_t>(wire_value(settings_.power));
  if (cooperative) return reflective_sheet_limit_binning_m;  // §9 Binning Mode: 1664 m at every level
  const double r = std::clamp(reflectivity, 0.0, 1.0);
  const double range =
      binning_gray_range_m[level] + (binning_white_range_m[level] - binning_gray_range_m[level]) * (r - 0.2) / 0.7;
  return std::max(range, 1.0);
}

std::optional<Firmware::PulseReturn> Firmware::first_return(Nanos t, bool certain, double min_width_ps) {
  if (fault_no_return_) return std::nullopt;
  std::optional<PulseReturn> best;
  for (const auto& target : scene_.targets) {
    const double d = target.motion.position_at(t);
    if (!passes_gates(settings_, d, target.cooperative)) continue;
    const double range = max_range_m(target.reflectivity, target.cooperative);
    if (d > range) continue;  // below the detection threshold
    if (best && best->distance_m <= d) continue;
    if (!certain && random_() >= detect_threshold) continue;
    const double ratio = range / d;
    const double strength = ratio * ratio;
    const double width_ps = target.pulse_width_ns ? *target.pulse_width_ns * 1000.0 : modelled_width_ps(strength);
    if (width_ps < min_width_ps) continue;  // too narrow: rejected like noise (§2 Min. Pulse Width, U41)
    best = PulseReturn{d, strength, target.cooperative, width_ps};
  }
  return best;
}

void Firmware::fire_pulse(Nanos t) {
  switch (settings_.mode) {
    case Mode::averaging:
      fire_averaging(t);
      break;
    case Mode::binning:
      fire_binning(t);
      break;
    case Mode::look_down:
      fire_look_down(t);
      break;
  }
}

void Firmware::emit(const std::vector<Reading>& readings, Nanos t) {
  latest_ = readings;
  for (const auto& poll : polls_) {
    for (const auto& reading : readings) reply(poll.port, false, encode_measurement(poll.to, reading), t);
  }
  polls_.clear();
  if (!settings_.continuous) return;
  auto& port = ports_[measurement_port()];
  drain(port, t);  // bytes already on the wire by t leave the UART first
  // One measurement may wait behind the one on the wire (U39); a measurement completing
  // while one already waits is skipped, so the §9 serial limits emerge from the pacing.
  if (port.last_line_start > t) {
    ++skipped_;
    return;
  }
  port.last_line_start = port.pacer.idle_at(t);
  const Address from = measurement_address();
  for (const auto& reading : readings) {
    if (auto line = encode_measurement(from, reading)) port.pacer.send(line->bytes(), t);
  }
}

void Firmware::record_error(int number, Nanos t) {
  last_error_ = number;
  if (!error_since_) error_since_ = t;
}

void Firmware::record_distance(double metres, Nanos) {
  last_distance_m_ = metres;
  last_error_ = 0;
  error_since_.reset();
}

}  // namespace rangekit::uls::emulator
