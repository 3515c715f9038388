// Result codes (§8.9, conformance L7): 0-50000 are results, two values above
// are special, everything else is invalid on the wire.
#pragma once

#include <cstdint>

#include "rangekit/core/result.hpp"

namespace rangekit::ls5 {

inline constexpr std::uint16_t max_result_code = 50000;
inline constexpr std::uint16_t derivative_zero_code = 25000;     // formula 8.2
inline constexpr std::uint16_t code_no_measurement_yet = 65534;  // §8.9
inline constexpr std::uint16_t code_no_signal = 65535;           // §8.9

enum class CodeKind : std::uint8_t { result, no_measurement_yet, no_signal };

struct ResultCode {
  std::uint16_t value = code_no_measurement_yet;
  CodeKind kind = CodeKind::no_measurement_yet;

  [[nodiscard]] constexpr bool is_result() const noexcept { return kind == CodeKind::result; }
  friend constexpr bool operator==(const ResultCode&, const ResultCode&) = default;
};

// Classifies a code read from the wire; 50001-65533 and anything above 65535 are errors.
Result<ResultCode> make_result_code(std::uint32_t raw);
// Never fails: for values the caller knows are in 0-50000 or special (emulator side).
// Inline: the stream decoder calls it for every record.
constexpr ResultCode classify_result_code(std::uint16_t value) noexcept {  // precondition: valid
  if (value == code_no_signal) return ResultCode{value, CodeKind::no_signal};
  if (value == code_no_measurement_yet) return ResultCode{value, CodeKind::no_measurement_yet};
  return ResultCode{value, CodeKind::result};
}

// Formula 8.1: distance from the start of the range, in mm. `code` in 0-50000.
double distance_mm(std::uint16_t code, double range_mm) noexcept;
// Formula 8.2: distance derivative in mm per measurement period. `code` in 0-50000.
double derivative_mm(std::uint16_t code, double range_mm) noexcept;
// Table 3.1, "Discreteness depending on the measurement range": up to 10 mm inclusive
// 0.0001, over 10 to 100 inclusive 0.001, over 100 to 1000 inclusive 0.01, more than
// 1000 mm 0.1 (table 5.1 steps up at the boundaries instead; the finer of the two is
// kept, conformance L63). How many decimals a distance of this sensor deserves.
double discreteness_mm(double range_mm) noexcept;
// Formula 8.1 for a classified code: an error for the special values.
Result<double> distance_from_code(ResultCode code, double range_mm);

// Formula 8.5: code = distance / range × 50000, rounded to the nearest code (halves
// away from zero). Distances outside 0..range are an error.
Result<std::uint16_t> code_from_distance(double distance_mm, double range_mm);

}  // namespace rangekit::ls5
