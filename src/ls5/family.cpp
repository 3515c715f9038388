#include "rangekit/ls5/family.hpp"

#include <array>
#include <cmath>

#include "rangekit/ls5/result_code.hpp"

namespace rangekit::ls5 {
namespace {

constexpr std::array channels{
    ChannelDescriptor{"code", Quantity::result_code, Unit::none, "the result code as sent, 0 to 65535"},
    ChannelDescriptor{"distance_mm", Quantity::distance, Unit::millimetre, "distance within the measuring range"},
    ChannelDescriptor{"derivative_mm", Quantity::distance_change, Unit::millimetre,
                      "difference of two results (a derivative)"},
};
constexpr const ChannelDescriptor& distance = channels[1];
constexpr const ChannelDescriptor& derivative = channels[2];

// A result: its distance; a derivative: the change. 65534 and 65535 (§9.3) carry neither.
// The decimals are those of the sensor's discreteness (table 3.1), as the stream prints them.
std::optional<Reading> reading(const Sample& sample) {
  if (sample.signal.value_or(SignalState::ok) != SignalState::ok) return std::nullopt;
  const int decimals = sample.resolution_mm ? decimals_of_step(*sample.resolution_mm) : 2;
  switch (sample.kind) {
    case SampleKind::ls5_result:
      if (sample.distance_mm) return Reading{&distance, *sample.distance_mm, decimals};
      return std::nullopt;
    case SampleKind::ls5_derivative:
      if (sample.derivative_mm) return Reading{&derivative, *sample.derivative_mm, decimals};
      return std::nullopt;
    default:
      return std::nullopt;
  }
}

// Results alone are judged, on the scale their own code shows: ±0.15 % of the range (table 3.1),
// one code a 50000th of it (formula 8.1), and a target crossing the whole range in a second.
std::optional<QualityInput> quality(const Sample& sample) {
  if (sample.kind != SampleKind::ls5_result) return std::nullopt;
  QualityInput input;
  if (sample.distance_mm) input.distance_m = *sample.distance_mm / 1000.0;
  if (const auto range = range_from_result_mm(sample)) {
    const double range_m = *range / 1000.0;
    input.scale = DistanceScale{
        .accuracy_m = 0.0015 * range_m, .resolution_m = range_m / max_result_code, .max_speed_mps = range_m};
  }
  return input;
}

constexpr FamilyDescriptor descriptor{
    .name = "ls5",
    .title = "Prizma LS5 laser triangulation sensor",
    .channels = channels,
    .reading = reading,
    .quality = quality,
};

}  // namespace

std::optional<double> range_from_result_mm(const Sample& sample) noexcept {
  if (!sample.code || *sample.code == 0 || !sample.distance_mm || !std::isfinite(*sample.distance_mm)) {
    return std::nullopt;
  }
  return *sample.distance_mm * max_result_code / *sample.code;
}

const FamilyDescriptor& family() noexcept { return descriptor; }

}  // namespace rangekit::ls5
