#include "rangekit/ls5/family.hpp"

#include <array>

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

constexpr FamilyDescriptor descriptor{
    .name = "ls5",
    .title = "Prizma LS5 laser triangulation sensor",
    .channels = channels,
    .reading = reading,
};

}  // namespace

const FamilyDescriptor& family() noexcept { return descriptor; }

}  // namespace rangekit::ls5
