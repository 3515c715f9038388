#include "rangekit/ls5/result_code.hpp"

#include <cmath>
#include <string>

namespace rangekit::ls5 {

Result<ResultCode> make_result_code(std::uint32_t raw) {
  if (raw <= max_result_code) return ResultCode{static_cast<std::uint16_t>(raw), CodeKind::result};
  if (raw == code_no_measurement_yet) return ResultCode{code_no_measurement_yet, CodeKind::no_measurement_yet};
  if (raw == code_no_signal) return ResultCode{code_no_signal, CodeKind::no_signal};
  return make_error(Errc::out_of_range, "LS5 result code " + std::to_string(raw) +
                                            " is invalid: results are 0-50000, 65534 no measurement yet, "
                                            "65535 no signal");
}

double distance_mm(std::uint16_t code, double range_mm) noexcept { return range_mm * code / max_result_code; }

double discreteness_mm(double range_mm) noexcept {
  if (range_mm <= 10) return 0.0001;
  if (range_mm <= 100) return 0.001;
  if (range_mm <= 1000) return 0.01;
  return 0.1;
}

double derivative_mm(std::uint16_t code, double range_mm) noexcept {
  return range_mm * (static_cast<double>(code) - derivative_zero_code) / max_result_code;
}

Result<double> distance_from_code(ResultCode code, double range_mm) {
  switch (code.kind) {
    case CodeKind::result:
      return distance_mm(code.value, range_mm);
    case CodeKind::no_measurement_yet:
      return make_error(Errc::out_of_range, "LS5 result code 65534: the sensor has not measured yet");
    case CodeKind::no_signal:
      return make_error(Errc::out_of_range, "LS5 result code 65535: no signal");
  }
  return make_error(Errc::out_of_range, "LS5 result code is not a result");
}

Result<std::uint16_t> code_from_distance(double distance, double range_mm) {
  if (!std::isfinite(distance) || !std::isfinite(range_mm) || range_mm <= 0.0) {
    return make_error(Errc::out_of_range, "a code needs a finite distance and a positive range");
  }
  const double code = std::round(distance / range_mm * max_result_code);  // std::round: halves away from zero
  if (code < 0.0 || code > max_result_code) {
    return make_error(Errc::out_of_range, "LS5 distance " + std::to_string(distance) + " mm is outside the range 0-" +
                                              std::to_string(range_mm) + " mm");
  }
  return static_cast<std::uint16_t>(code);
}

}  // namespace rangekit::ls5
