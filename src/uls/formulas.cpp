#include "rangekit/uls/formulas.hpp"

#include <algorithm>
#include <cmath>

#include "rangekit/core/text.hpp"
#include "rangekit/core/units.hpp"

namespace rangekit::uls {
namespace {

constexpr std::array<std::uint32_t, 10> bauds{1200, 2400, 4800, 9600, 14400, 19200, 38400, 57600, 115200, 230400};

// §9 Binning Mode "Accuracy and Maximum Range" rows; n = 8 continues the
// doubling (U20). Labels follow the Interface Program's "2.5 (13)" (§2, U33).
constexpr std::array<BinSizeInfo, 9> bin_sizes{{
    {BinSize::inch_1, 1, 2.5, 13, "2.5 (13)"},
    {BinSize::inches_2, 2, 5.1, 26, "5.1 (26)"},
    {BinSize::inches_4, 4, 10.2, 52, "10.2 (52)"},
    {BinSize::inches_8, 8, 20.4, 104, "20.4 (104)"},
    {BinSize::inches_16, 16, 40.8, 208, "40.8 (208)"},
    {BinSize::inches_32, 32, 81.6, 416, "81.6 (416)"},
    {BinSize::inches_64, 64, 163.2, 832, "163.2 (832)"},
    {BinSize::inches_128, 128, 326.4, 1664, "326.4 (1664)"},
    {BinSize::inches_256, 256, 652.8, 3329, "652.8 (1664)"},  // §9's 1664 m reach (U131)
}};

}  // namespace

double output_period_s(std::uint32_t pulses_per_measurement, double prf_hz) noexcept {
  return static_cast<double>(pulses_per_measurement) / prf_hz;
}

double output_rate_hz(double prf_hz, std::uint32_t pulses_per_measurement) noexcept {
  return prf_hz / static_cast<double>(pulses_per_measurement);
}

double character_time_s(std::uint32_t baud) noexcept {
  return reference_character_time_s * static_cast<double>(reference_baud) / static_cast<double>(baud);
}

double line_time_s(std::size_t characters, std::uint32_t baud) noexcept {
  return static_cast<double>(characters) * character_time_s(baud);
}

double max_line_rate_hz(std::size_t characters, std::uint32_t baud) noexcept {
  return 1.0 / line_time_s(characters, baud);
}

std::span<const std::uint32_t> baud_choices() noexcept { return bauds; }

bool is_baud_choice(std::uint32_t baud) noexcept { return std::find(bauds.begin(), bauds.end(), baud) != bauds.end(); }

std::span<const BinSizeInfo> bin_size_table() noexcept { return bin_sizes; }

const BinSizeInfo& bin_size_info(BinSize size) noexcept {
  const auto index = static_cast<std::size_t>(size);
  return bin_sizes[index < bin_sizes.size() ? index : 0];
}

double bin_size_m(BinSize size) noexcept {
  return units::inches_to_metres(static_cast<double>(bin_size_info(size).inches));
}

double bin_max_range_m(BinSize size) noexcept { return bins_per_range * bin_size_m(size); }

double bin_usable_range_m(BinSize size) noexcept {
  return std::min(bin_max_range_m(size), reflective_sheet_limit_binning_m);
}

std::optional<double> loop_current_ma(double distance, double range_at_4ma, double range_at_20ma) noexcept {
  if (range_at_4ma == range_at_20ma) return std::nullopt;
  const double span = loop_max_ma - loop_min_ma;
  const double current = loop_min_ma + span * (distance - range_at_4ma) / (range_at_20ma - range_at_4ma);
  return std::clamp(current, loop_min_ma, loop_max_ma);
}

std::uint64_t trip_timeout_pulses(double seconds) noexcept {
  if (!(seconds > 0)) return 0;
  const double pulses = std::round(seconds * trip_timeout_pulses_per_second);
  if (pulses >= static_cast<double>(max_trip_timeout_pulses)) return max_trip_timeout_pulses;
  return static_cast<std::uint64_t>(pulses);
}

double trip_timeout_seconds(std::uint64_t pulses) noexcept {
  return static_cast<double>(pulses) / trip_timeout_pulses_per_second;
}

HexText to_hex_text(std::uint64_t value) noexcept {
  HexText text;
  std::size_t width = 1;
  while (width < 16 && (value >> (4 * width)) != 0) ++width;
  text::write_hex(value, width, text.digits.data());
  text.size = width;
  return text;
}

std::optional<std::uint64_t> parse_trip_timeout(std::string_view hex) noexcept { return text::parse_hex(hex, 8); }

double pulses_to_seconds(std::uint64_t pulses, double prf_hz) noexcept { return static_cast<double>(pulses) / prf_hz; }

double seconds_to_pulses(double seconds, double prf_hz) noexcept { return seconds * prf_hz; }

TimeBetweenEvents tbe_from_pulses(std::uint64_t pulses) noexcept {
  if (pulses == 0 || pulses > max_tbe_pulses) return {TimeBetweenEvents::Kind::overflow, 0};
  return {TimeBetweenEvents::Kind::pulses, static_cast<std::uint16_t>(pulses)};
}

std::optional<double> tbe_seconds(const TimeBetweenEvents& event, double prf_hz) noexcept {
  if (event.kind != TimeBetweenEvents::Kind::pulses) return std::nullopt;
  return pulses_to_seconds(event.pulses, prf_hz);
}

double tbe_max_seconds(double prf_hz) noexcept { return pulses_to_seconds(max_tbe_pulses, prf_hz); }

double look_down_latency_s(double prf_hz) noexcept { return pulses_to_seconds(look_down_decision_pulses, prf_hz); }

double look_down_uncertainty_s(double prf_hz) noexcept { return 1.0 / prf_hz; }

double to_metres(double value, Units units) noexcept {
  return units == Units::feet ? units::feet_to_metres(value) : value;
}

double from_metres(double metres, Units units) noexcept {
  return units == Units::feet ? units::metres_to_feet(metres) : metres;
}

double distance_limit(double metres, Units units) noexcept {
  const double scale = units == Units::metres ? 1000.0 : 100.0;  // the decimals of format_distance
  return std::round(from_metres(metres, units) * scale) / scale;
}

bool distance_within(double value, Units units, double min_m, double max_m) noexcept {
  // Both sides are decimal text of at most 2-3 decimals: allow for their binary rounding only.
  constexpr double slack = 1e-9;
  return value >= distance_limit(min_m, units) - slack && value <= distance_limit(max_m, units) + slack;
}

double distance_to_metres(double value, Units units, double min_m, double max_m) noexcept {
  const double metres = to_metres(value, units);
  if (!distance_within(value, units, min_m, max_m)) return metres;
  return std::clamp(metres, min_m, max_m);
}

std::optional<std::uint8_t> unit_address_char(std::uint64_t value) noexcept {
  if (value < first_unit_address || value > last_unit_address) return std::nullopt;
  return static_cast<std::uint8_t>(value);
}

std::string address_text(std::uint8_t address) {
  if (address >= 0x21 && address < 0x7F) return std::string(1, static_cast<char>(address));
  return "0x" + text::hex_byte(address);
}

std::optional<std::uint8_t> parse_unit_address(std::string_view text) {
  std::optional<std::uint64_t> value;
  if (text.size() == 1) {
    value = static_cast<unsigned char>(text[0]);
  } else if (text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
    value = text::parse_hex(text.substr(2), 2);
  } else {
    value = text::parse_unsigned(text, 3);
  }
  if (!value || *value < first_unit_address || *value > last_unit_address) return std::nullopt;
  return static_cast<std::uint8_t>(*value);
}

}  // namespace rangekit::uls
