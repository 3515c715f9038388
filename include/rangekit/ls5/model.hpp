// The sensor as ordered (LS5 §3, §5, §7): the ordering code, the accuracy it
// implies, and the load a current-loop output needs.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "rangekit/core/result.hpp"
#include "rangekit/ls5/formulas.hpp"

namespace rangekit::ls5 {

enum class DigitalInterface : std::uint8_t { rs232, rs485, rs485_ethernet };

// §5 "LS5-100/200-485/E-I4-2-12-A": lower boundary / range - interface - analog
// output - discrete outputs - supply voltage - case (conformance L25).
struct OrderingCode {
  double lower_boundary_mm = 0;
  double range_mm = 0;
  DigitalInterface interface = DigitalInterface::rs485;
  AnalogRange analog = current_4_20_mA;
  std::string_view analog_code;  // "I4", "I0" or "U10"; points into static storage
  std::uint8_t discrete_outputs = 2;
  std::uint8_t supply_volts = 12;
  char case_type = 'A';
};

Result<OrderingCode> parse_ordering_code(std::string_view text);
[[nodiscard]] bool has_ethernet(const OrderingCode& code) noexcept;

// §3 table 3.1: limit of the error reduced to the range, ±0.15 % digital and
// ±0.25 % analog (note 2: a 5 mm sensor errs by at most 0.0075 mm digitally).
inline constexpr double digital_error_fraction = 0.0015;
inline constexpr double analog_error_fraction = 0.0025;
constexpr double digital_error_limit_mm(double range_mm) noexcept { return range_mm * digital_error_fraction; }
constexpr double analog_error_limit_mm(double range_mm) noexcept { return range_mm * analog_error_fraction; }

// §7: minimum load of the current output, R_L > (I_max × U_P − 0.125 W) / I_max²,
// in ohms; I_max is 20 or 24 mA, U_P the supply of the current generator.
double minimum_load_ohms(double max_current_ma, double supply_volts) noexcept;

}  // namespace rangekit::ls5
