// The figures of the ULS pulse model (§9, docs/emulator-uls.md), shared by the modes.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>

#include "rangekit/uls/emulator/firmware.hpp"

namespace rangekit::uls::emulator {

inline constexpr double minimum_range_m = 0.15;        // §9
inline constexpr double cooperative_range_m = 1700.0;  // §9 reflective sheet, every power level
// §9 maximum ranges by power level (high, medium, low).
inline constexpr std::array<double, 3> white_range_m{266.0, 228.0, 188.0};  // 90% white
inline constexpr std::array<double, 3> gray_range_m{133.0, 114.0, 94.0};    // 20% gray
// §9 Binning Mode maximum ranges by power level, reached with the factory BH and PPM (U125).
inline constexpr std::array<double, 3> binning_white_range_m{450.0, 300.0, 250.0};  // 90% white
inline constexpr std::array<double, 3> binning_gray_range_m{225.0, 150.0, 125.0};   // 20% gray
// A target at the binning maximum range lands a factory bin's worth of hits on average (128 of
// 1024 pulses): found in about half of the measurements there, fewer beyond (U125).
inline constexpr double binning_edge_probability = 128.0 / 1024.0;
// Single-pulse timing jitter (one sigma) and the time quantum of a pulse (docs/emulator-uls.md).
inline constexpr double jitter_m = 0.02;
inline constexpr double cooperative_jitter_m = 0.01;
inline constexpr double quantum_m = 0.05;
inline constexpr std::uint32_t dither_cycle = 32;  // §3
inline constexpr double detect_probability = 0.99;
// The same as a threshold on the engine's raw 64-bit output: no conversion to double per pulse.
inline constexpr auto detect_threshold = static_cast<std::uint64_t>(detect_probability * 18446744073709551616.0);
// Received pulse widths (U40): about the 8 ns transmit pulse (§3) for a return at the
// detection limit, wider as the signal grows (time over threshold, logarithmic).
inline constexpr double weakest_width_ns = 4.0;
inline constexpr double width_ns_per_doubling = 6.0;
inline constexpr double dust_width_ns = 3.0;   // dust near the unit: a weak, narrow return
inline constexpr double noise_window_m = 0.5;  // narrowest noise-filter window (U48)
// The §3 binning restart rule: at most this many targets per burst.
inline constexpr std::size_t restart_targets = max_binning_targets;

// Whether a target at `d` can answer at all: beyond the minimum range, inside the short and
// long gates (0 = off) and, with the cooperative filter on, a cooperative target (§8 SG, LG, FL).
inline bool passes_gates(const Settings& settings, double d, bool cooperative) noexcept {
  if (d < minimum_range_m) return false;
  if (settings.short_gate_m > 0 && d < settings.short_gate_m) return false;
  if (settings.long_gate_m > 0 && d > settings.long_gate_m) return false;
  return !settings.cooperative_filter || cooperative;
}

}  // namespace rangekit::uls::emulator
