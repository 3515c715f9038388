#include "rangekit/ls5/formulas.hpp"

namespace rangekit::ls5 {

// Formula 8.3 as conformance L8 reads it: linear between K_n and K_v, held at the
// end values outside; K_v < K_n inverts; K_v = K_n leaves the output at A_min.
double analog_output(const AnalogRange& range, const AnalogLimits& limits, std::uint16_t code) noexcept {
  const double k = code;
  const double kn = limits.lower;
  const double kv = limits.upper;
  if (limits.lower == limits.upper) return range.min;
  if (limits.lower < limits.upper) {
    if (k <= kn) return range.min;
    if (k >= kv) return range.max;
  } else {
    if (k <= kv) return range.max;
    if (k >= kn) return range.min;
  }
  return range.min + (range.max - range.min) * (k - kn) / (kv - kn);
}

double analog_output(const AnalogRange& range, const AnalogLimits& limits, ResultCode code,
                     std::optional<std::uint16_t> last_result_code) noexcept {
  switch (code.kind) {
    case CodeKind::result:
      return analog_output(range, limits, code.value);
    case CodeKind::no_measurement_yet:
      return range.min;  // §8.2: "the state of no result"
    case CodeKind::no_signal:
      break;
  }
  // §8.10: "No signal" drives the output to the extreme nearer the last measured value.
  if (!last_result_code) return range.min;
  const double last = analog_output(range, limits, *last_result_code);
  return last < (range.min + range.max) / 2.0 ? range.min : range.max;
}

}  // namespace rangekit::ls5
