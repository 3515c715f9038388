// Pure formulas and tables from the ULS document: output timing (§2, §9),
// serial pacing (U19), bin sizes (§8, §9, U20), the 4-20 mA loop (§6, U23),
// trip-point timeout and time between events (§3, §8, U12, U21), look down (§3).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "rangekit/uls/types.hpp"

namespace rangekit::uls {

// --- Output rate (§2 Pulses/Measure note, §3 Averaging, §9 Output Data Rate) ---
// One measurement every PPM / PRF seconds.
double output_period_s(std::uint32_t pulses_per_measurement, double prf_hz) noexcept;
double output_rate_hz(double prf_hz, std::uint32_t pulses_per_measurement) noexcept;

// --- Serial pacing (§9, U19) ---
inline constexpr std::uint32_t reference_baud = 115200;
inline constexpr double reference_character_time_s = 100e-6;  // "approximately 100 µs per character"
double character_time_s(std::uint32_t baud) noexcept;
double line_time_s(std::size_t characters, std::uint32_t baud) noexcept;
// Fastest rate at which lines of `characters` characters can leave the port.
double max_line_rate_hz(std::size_t characters, std::uint32_t baud) noexcept;

// §9 "Baud Rate Choices"; 230400 only by serial command.
std::span<const std::uint32_t> baud_choices() noexcept;
bool is_baud_choice(std::uint32_t baud) noexcept;
inline constexpr std::uint32_t interface_program_max_baud = 115200;
inline constexpr std::uint32_t serial_command_max_baud = 230400;

// --- Bin size (§8 Set/Get Bin Size, §9 Binning Mode table, U20, U33) ---
inline constexpr std::uint32_t bins_per_range = 512;
inline constexpr double reflective_sheet_limit_binning_m = 1664.0;  // §9
struct BinSizeInfo {
  BinSize size;
  std::uint32_t inches;
  double accuracy_cm;                // §9 column ("±2.5 cm typical" ...); n = 8 by the same rule
  std::uint32_t max_range_m;         // §9 column as printed (whole metres); n = 8: 3329 (U20)
  std::string_view interface_label;  // how the Interface Program lists it: "2.5 (13)" (§2, U33)
};
std::span<const BinSizeInfo> bin_size_table() noexcept;
const BinSizeInfo& bin_size_info(BinSize size) noexcept;
double bin_size_m(BinSize size) noexcept;
// 512 bins of the bin size (U20), exact: 13.0048 m for 1 inch.
double bin_max_range_m(BinSize size) noexcept;
// Same, capped by the 1664 m reflective-sheet limit of §9.
double bin_usable_range_m(BinSize size) noexcept;

// --- 4-20 mA loop (§6, U23) ---
inline constexpr double loop_min_ma = 4.0;
inline constexpr double loop_max_ma = 20.0;
// I = 4 + 16 (d - AL) / (AH - AL), clamped to 4-20 mA; AH < AL inverts.
// None when AL == AH (the unit refuses that range, error 83).
std::optional<double> loop_current_ma(double distance, double range_at_4ma, double range_at_20ma) noexcept;
// §6: the internally powered loop gives about 9 V of compliance, which limits the
// sense resistor: 9 V / 20 mA = 450 ohms.
inline constexpr double loop_compliance_volts = 9.0;
constexpr double max_sense_resistor_ohms(double compliance_volts = loop_compliance_volts,
                                         double full_scale_ma = 20.0) noexcept {
  return compliance_volts / (full_scale_ma / 1000.0);
}

// --- Trip point timeout TT (§8 "(seconds * 3000) in hexadecimal", §3, U21) ---
inline constexpr std::uint32_t trip_timeout_pulses_per_second = 3000;
inline constexpr std::uint64_t rereference_pulses = 1'080'000;        // §3: "approximately 6 minutes"
inline constexpr std::uint64_t short_timeout_pulses = 8'000;          // §3: "approximately 3 seconds"
inline constexpr std::uint64_t max_trip_timeout_pulses = 0xFFFFFFFF;  // 8 hex digits (U18)
std::uint64_t trip_timeout_pulses(double seconds) noexcept;           // rounded to the nearest pulse
double trip_timeout_seconds(std::uint64_t pulses) noexcept;

// Upper-case hex without leading zeros, as TT carries it: 1080000 -> "107AC0".
struct HexText {
  std::array<char, 16> digits{};
  std::size_t size = 0;
  [[nodiscard]] std::string_view view() const noexcept { return {digits.data(), size}; }
};
HexText to_hex_text(std::uint64_t value) noexcept;
// 1-8 hex digits, either case (U18); none otherwise.
std::optional<std::uint64_t> parse_trip_timeout(std::string_view hex) noexcept;

// --- Pulses and time at a PRF (§3 look down, time between events) ---
double pulses_to_seconds(std::uint64_t pulses, double prf_hz) noexcept;
double seconds_to_pulses(double seconds, double prf_hz) noexcept;

// --- Time between events (§3, §8, U12) ---
inline constexpr std::uint32_t max_tbe_pulses = 0xFFFF;
// The report for a no-presence-to-presence gap of `pulses`: more than 65535 (or 0,
// which the 4-digit field cannot tell from overflow) reports overflow, "0000".
TimeBetweenEvents tbe_from_pulses(std::uint64_t pulses) noexcept;
// Seconds the report stands for at `prf_hz`; none for no presence and overflow.
std::optional<double> tbe_seconds(const TimeBetweenEvents& event, double prf_hz) noexcept;
// Longest gap the report can carry at `prf_hz` (65535 pulses, ~22 s at 3 kHz).
double tbe_max_seconds(double prf_hz) noexcept;

// --- Look down response (§3) ---
inline constexpr std::uint32_t look_down_decision_pulses = 30;
double look_down_latency_s(double prf_hz) noexcept;      // 30 pulses / PRF
double look_down_uncertainty_s(double prf_hz) noexcept;  // ± one pulse: 1 / PRF

// --- Distances in user units (§8 MU; 1 ft = 0.3048 m) ---
double to_metres(double value, Units units) noexcept;
double from_metres(double metres, Units units) noexcept;
// A §8 distance limit (metres) as the unit writes it in `units`, at the §9 resolution
// (1 mm or 0.01 ft): 1700 m = 5577.43 ft (U30, U76).
double distance_limit(double metres, Units units) noexcept;
// Whether a distance in user units lies within [min_m, max_m] written in those units, so
// that every distance a get reports is accepted back by the set (U76): 5577.43 ft is
// within 1700 m although 5577.43 x 0.3048 = 1700.0007.
bool distance_within(double value, Units units, double min_m, double max_m) noexcept;
// The metres a distance in user units stands for, kept within [min_m, max_m]: a value
// distance_within accepts at a limit is that limit (5577.43 ft -> 1700 m).
double distance_to_metres(double value, Units units, double min_m, double max_m) noexcept;

// --- Unit address character (§8 Set/Get Unit Address, U5) ---
// The get reply carries the character's code in decimal: 'Z' -> 90.
constexpr int unit_address_value(std::uint8_t address_char) noexcept { return address_char; }
// The character for a decimal value in 0x30..0xEF, none otherwise.
std::optional<std::uint8_t> unit_address_char(std::uint64_t value) noexcept;
// "A", or "0xC5" for bytes a terminal cannot show.
std::string address_text(std::uint8_t address);
// Reads "A", "0x41" or "65"; none when it is not a unit address 0x30..0xEF.
std::optional<std::uint8_t> parse_unit_address(std::string_view text);

}  // namespace rangekit::uls
