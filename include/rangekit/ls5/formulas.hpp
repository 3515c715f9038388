// The LS5's arithmetic (§8) as pure functions: analog output (8.3), discrete
// outputs (8.4), latching recalculation (8.6/8.7), derivative (§8.8), serial
// timing and output period (§8.4). Result-code conversions are in result_code.hpp.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "rangekit/core/result.hpp"
#include "rangekit/ls5/logical_values.hpp"
#include "rangekit/ls5/result_code.hpp"
#include "rangekit/ls5/settings.hpp"

namespace rangekit::ls5 {

// ---- Analog output, formula 8.3 (§8.10, conformance L8) ----

struct AnalogRange {
  double min;  // A_min
  double max;  // A_max
  std::string_view unit;
};
inline constexpr AnalogRange current_4_20_mA{4.0, 20.0, "mA"};
inline constexpr AnalogRange current_0_20_mA{0.0, 20.0, "mA"};
inline constexpr AnalogRange voltage_0_10_V{0.0, 10.0, "V"};

struct AnalogLimits {
  std::uint16_t lower;  // K_n, parameters 11/12
  std::uint16_t upper;  // K_v, parameters 13/14
};

// Formula 8.3 for a result code K (0-50000).
double analog_output(const AnalogRange& range, const AnalogLimits& limits, std::uint16_t code) noexcept;
// The output for any code: 65534 gives A_min; 65535 the extreme nearer the output of
// the last result (A_min if none yet).
double analog_output(const AnalogRange& range, const AnalogLimits& limits, ResultCode code,
                     std::optional<std::uint16_t> last_result_code) noexcept;

// ---- Discrete outputs, formula 8.4 (§8.11, conformance L9) ----

struct DiscreteOutputSetting {
  bool enabled = false;
  bool initial_state = false;  // N
  friend constexpr bool operator==(const DiscreteOutputSetting&, const DiscreteOutputSetting&) = default;
};
struct DiscreteOutputsSetting {
  DiscreteOutputSetting output1;  // first hex digit of parameter 15
  DiscreteOutputSetting output2;  // second hex digit
  friend constexpr bool operator==(const DiscreteOutputsSetting&, const DiscreteOutputsSetting&) = default;
};
// Parameter 15: digit 0 disabled, 1 enabled with N = 0, 2 enabled with N = 1.
Result<DiscreteOutputsSetting> decode_discrete_outputs(std::uint8_t value);
std::uint8_t encode_discrete_outputs(const DiscreteOutputsSetting& setting) noexcept;

struct Swings {
  std::uint16_t first;   // K_OC1
  std::uint16_t second;  // K_OC2
};
// Formula 8.4 for any 16-bit code, 65534/65535 included; a disabled output is 0.
bool discrete_output_state(const DiscreteOutputSetting& setting, const Swings& swings, std::uint16_t code) noexcept;

// ---- Latching with recalculation, formulas 8.6/8.7 (§8.14, conformance L10) ----

// G_min = clamp(int(K - D/2), 0, 50000), int rounding halves away from zero.
std::uint16_t latch_lower_limit(std::uint16_t code, std::uint16_t fixed_range) noexcept;
// G_max = clamp(int(K + D/2), 0, 50000).
std::uint16_t latch_upper_limit(std::uint16_t code, std::uint16_t fixed_range) noexcept;

struct LatchRecalculation {
  bool recalculated = false;  // false for modes 00/01 and when the latched code is not a result
  std::uint16_t lower = 0;    // G_min
  std::uint16_t upper = 0;    // G_max
  ParameterWrites writes;     // the parameter bytes that change, low byte first
  bool to_rom = false;        // modes 03, 05, 07, 09 also store the new limits
};

// What latching `latched` does under latching byte `mode` (parameter 1F), with the
// fixed ranges of parameters 23/24 (analog) and 25/26 (discrete outputs).
Result<LatchRecalculation> recalculate_on_latch(std::uint8_t mode, ResultCode latched, std::uint16_t analog_fixed_range,
                                                std::uint16_t discrete_fixed_range);

// ---- Derivative, §8.8 (conformance L11) ----

// clamp(25000 + (current - previous), 0, 50000)
std::uint16_t derivative_code(std::uint16_t current, std::uint16_t previous) noexcept;

// ---- Serial timing and output period, §8.4 (conformance L13) ----

inline constexpr std::size_t stream_record_bytes = 7;  // '!' + 5 digits + CR

// 1 start bit + 8 data bits + parity bit if any + stop bits.
unsigned bits_per_byte(const ByteFormat& format) noexcept;
// Time on the line for `bytes` bytes.
double transmit_time_ms(std::size_t bytes, std::uint32_t baud, const ByteFormat& format) noexcept;
double stream_record_time_ms(std::uint32_t baud, const ByteFormat& format) noexcept;
// Most stream records per second the line carries.
double max_stream_rate_hz(std::uint32_t baud, const ByteFormat& format) noexcept;
// The slowest baud code whose line carries `rate_hz` stream records, among those
// `firmware` offers; nullopt when none does.
std::optional<BaudRateInfo> slowest_baud_for_stream_rate(double rate_hz, const ByteFormat& format,
                                                         const FirmwareVersion& firmware) noexcept;
// T = n × t (§8.4): measurement period code (0.1 ms units) times thinning n.
double output_period_ms(std::uint16_t period_code, std::uint8_t thinning) noexcept;

}  // namespace rangekit::ls5
