// Look-down mode (§3, §8 MM 3): a reference distance, presence decided over 30 pulses,
// re-referencing, and the trip line or time between events it reports.
#include "rangekit/uls/emulator/firmware.hpp"

#include <algorithm>
#include <cmath>

namespace rangekit::uls::emulator {

void Firmware::fire_look_down(Nanos t) {
  const std::uint64_t pulse = next_pulse_;
  // Look down fires without averaging: a target within range always answers (U38).
  const auto hit = first_return(t, true);
  const std::optional<double> d = hit ? std::optional<double>(hit->distance_m) : std::nullopt;
  if (!reference_m_) {
    // Reference on start (§3): the longest distance over the first 30 pulses.
    if (d) reference_candidate_m_ = std::max(reference_candidate_m_, *d);
    if (++reference_pulses_ >= look_down_decision_pulses && reference_candidate_m_ > 0) {
      reference_m_ = reference_candidate_m_;
      have_no_presence_edge_ = true;
      no_presence_edge_pulse_ = pulse;
    }
    return;
  }
  const bool presence_pulse = d && *d < *reference_m_ - settings_.trip_point_m;
  if (presence_pulse != present_) {
    // 30 consecutive pulses decide a change (§3, U34).
    if (++disagreeing_ >= look_down_decision_pulses) change_presence(presence_pulse, pulse, t);
  } else {
    disagreeing_ = 0;
  }
  if (present_ && d) {
    // Re-reference on a distance that stays put for TT pulses while tripped (§3). The trip is
    // released like any end of presence: `$BM,0`, or with TB on `$0` starting the no-presence
    // time the next `$XXXX` counts (U73).
    if (std::abs(*d - stable_m_) > std::max(settings_.trip_point_m / 2, 0.1)) {
      stable_m_ = *d;
      stable_pulses_ = 0;
    } else if (++stable_pulses_ >= settings_.trip_timeout_pulses) {
      reference_m_ = *d;
      change_presence(false, pulse, t);
    }
  }
  if (!present_ && d && *d > *reference_m_ + settings_.trip_point_m / 2) {
    // A longer distance while not tripped becomes the reference after about 2 s (§3).
    longer_m_ = longer_pulses_ == 0 ? *d : std::max(longer_m_, *d);
    if (++longer_pulses_ >= 2ULL * run_prf_) {
      reference_m_ = longer_m_;
      longer_pulses_ = 0;
    }
  } else {
    longer_pulses_ = 0;
  }
}

void Firmware::change_presence(bool present, std::uint64_t pulse, Nanos t) {
  present_ = present;
  disagreeing_ = 0;
  stable_pulses_ = 0;
  if (present) {
    // §3: "the number of fire pulses between not present and present events" (U12).
    presence_tbe_ = have_no_presence_edge_ ? tbe_from_pulses(pulse - no_presence_edge_pulse_)
                                           : TimeBetweenEvents{TimeBetweenEvents::Kind::overflow, 0};
  } else {
    no_presence_edge_pulse_ = pulse;
    have_no_presence_edge_ = true;
  }
  emit({look_down_state()}, t);
}

Reading Firmware::look_down_state() const noexcept {
  // Before the first detection the trip line is low (§3), so OFF / `$0` (U71). With TB on a
  // presence is told by its `$XXXX`, the line sent at its start (§8, U72).
  if (!settings_.time_between_events) return LookDownReading{present_};
  return present_ ? presence_tbe_ : TimeBetweenEvents{};
}

}  // namespace rangekit::uls::emulator
