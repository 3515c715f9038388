#include "rangekit/ls5/formulas.hpp"

#include <cmath>
#include <string>

#include "ls5/messages.hpp"

namespace rangekit::ls5 {
namespace {

// int(x) of formulas 8.6/8.7 (rounding to the nearest, halves away from zero, L10),
// then held to 0..50000. K ± D/2 is a multiple of 0.5, so doubles are exact here.
std::uint16_t clamped_limit(double unrounded) noexcept {
  const double rounded = std::round(unrounded);
  if (rounded < 0.0) return 0;
  if (rounded > max_result_code) return max_result_code;
  return static_cast<std::uint16_t>(rounded);
}

void add_code_writes(ParameterWrites& writes, std::uint8_t low_address, std::uint16_t code) noexcept {
  writes.items[writes.count++] = ParameterWrite{low_address, static_cast<std::uint8_t>(code & 0xFFU)};
  writes.items[writes.count++] =
      ParameterWrite{static_cast<std::uint8_t>(low_address + 1), static_cast<std::uint8_t>(code >> 8U)};
}

}  // namespace

std::uint16_t latch_lower_limit(std::uint16_t code, std::uint16_t fixed_range) noexcept {
  return clamped_limit(static_cast<double>(code) - fixed_range / 2.0);
}

std::uint16_t latch_upper_limit(std::uint16_t code, std::uint16_t fixed_range) noexcept {
  return clamped_limit(static_cast<double>(code) + fixed_range / 2.0);
}

Result<LatchRecalculation> recalculate_on_latch(std::uint8_t mode_byte, ResultCode latched,
                                                std::uint16_t analog_fixed_range, std::uint16_t discrete_fixed_range) {
  const std::optional<LatchingMode> mode = latching_mode_from_byte(mode_byte);
  if (!mode) {
    return make_error(Errc::out_of_range, "LS5 latching mode " + text::hex_byte(mode_byte) +
                                              " is not one of 00-09 (table 9.2, parameter 1F)");
  }
  LatchRecalculation outcome;
  outcome.to_rom = latching_writes_rom(*mode);
  if (*mode == LatchingMode::off || *mode == LatchingMode::latch_only || !latched.is_result()) return outcome;

  const bool analog = *mode == LatchingMode::analog_limits || *mode == LatchingMode::analog_limits_to_rom;
  const std::uint16_t span = analog ? analog_fixed_range : discrete_fixed_range;
  outcome.recalculated = true;
  outcome.lower = latch_lower_limit(latched.value, span);
  outcome.upper = latch_upper_limit(latched.value, span);

  switch (*mode) {
    case LatchingMode::analog_limits:
    case LatchingMode::analog_limits_to_rom:
      add_code_writes(outcome.writes, address::analog_lower_low, outcome.lower);
      add_code_writes(outcome.writes, address::analog_upper_low, outcome.upper);
      break;
    case LatchingMode::output1_limits:
    case LatchingMode::output1_limits_to_rom:
      add_code_writes(outcome.writes, address::output1_first_swing_low, outcome.lower);
      add_code_writes(outcome.writes, address::output1_second_swing_low, outcome.upper);
      break;
    case LatchingMode::output2_limits:
    case LatchingMode::output2_limits_to_rom:
      add_code_writes(outcome.writes, address::output2_first_swing_low, outcome.lower);
      add_code_writes(outcome.writes, address::output2_second_swing_low, outcome.upper);
      break;
    case LatchingMode::output1_lower_output2_upper:
    case LatchingMode::output1_lower_output2_upper_to_rom:
      // §8.14 welding example: "the lower limit of the 1st discrete output and the
      // upper limit of the 2nd" are the first swing of output 1 and the second of output 2.
      add_code_writes(outcome.writes, address::output1_first_swing_low, outcome.lower);
      add_code_writes(outcome.writes, address::output2_second_swing_low, outcome.upper);
      break;
    case LatchingMode::off:
    case LatchingMode::latch_only:
      break;
  }
  return outcome;
}

}  // namespace rangekit::ls5
