#include "rangekit/ls5/formulas.hpp"

#include <string>

#include "ls5/messages.hpp"

namespace rangekit::ls5 {
namespace {

// One hex digit of parameter 15: 0 disabled, 1 enabled with N = 0, 2 enabled with N = 1.
bool decode_digit(unsigned digit, DiscreteOutputSetting& setting) noexcept {
  if (digit > 2) return false;
  setting.enabled = digit != 0;
  setting.initial_state = digit == 2;
  return true;
}

unsigned encode_digit(const DiscreteOutputSetting& setting) noexcept {
  if (!setting.enabled) return 0;
  return setting.initial_state ? 2U : 1U;
}

}  // namespace

Result<DiscreteOutputsSetting> decode_discrete_outputs(std::uint8_t value) {
  DiscreteOutputsSetting setting;
  if (!decode_digit(value >> 4U, setting.output1) || !decode_digit(value & 0x0FU, setting.output2)) {
    return make_error(Errc::out_of_range, "LS5 discrete outputs setting " + text::hex_byte(value) +
                                              " is not one of 00-02, 10-12, 20-22 (table 9.2, parameter 15)");
  }
  return setting;
}

std::uint8_t encode_discrete_outputs(const DiscreteOutputsSetting& setting) noexcept {
  return static_cast<std::uint8_t>((encode_digit(setting.output1) << 4U) | encode_digit(setting.output2));
}

// Formula 8.4 (L9): not N between the swings inclusive, N outside. 65534/65535 are
// above every swing (0-50000), so they give N, as §8.11 says the formula holds.
bool discrete_output_state(const DiscreteOutputSetting& setting, const Swings& swings, std::uint16_t code) noexcept {
  if (!setting.enabled) return false;
  const bool between = swings.first <= code && code <= swings.second;
  return between ? !setting.initial_state : setting.initial_state;
}

}  // namespace rangekit::ls5
