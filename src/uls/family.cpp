#include "rangekit/uls/family.hpp"

#include <algorithm>
#include <array>

#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/formulas.hpp"
#include "rangekit/uls/interface_log.hpp"

namespace rangekit::uls {
namespace {

constexpr std::array channels{
    ChannelDescriptor{"distance_m", Quantity::distance, Unit::metre, "averaged distance (averaging mode)"},
    ChannelDescriptor{"pulse_width_ns", Quantity::pulse_width, Unit::nanosecond,
                      "width of the returned pulse (picoseconds on the wire)"},
    ChannelDescriptor{"targets", Quantity::distance, Unit::metre, "the targets of one binning burst, nearest first"},
    ChannelDescriptor{"presence", Quantity::presence, Unit::none, "look down: 1 a target is there, 0 it left"},
    ChannelDescriptor{"pulses_between_events", Quantity::pulse_count, Unit::none,
                      "look down: laser pulses between the last two edges"},
    ChannelDescriptor{"error", Quantity::error_number, Unit::none, "the error number the unit sent"},
};
constexpr const ChannelDescriptor& distance = channels[0];
constexpr const ChannelDescriptor& targets = channels[2];
constexpr const ChannelDescriptor& presence = channels[3];
// Metres with the stream's 4 decimals: 1 mm, and 0.01 ft (3.048 mm) in feet (§9).
constexpr int metre_decimals = 4;

// Averaging: its distance. Binning: the nearest target, the Interface Program's "first target
// the laser sees" (§2 Display/Target Selection). Look down: the edge, 1 or 0. A §10 error
// (a burst with no target, $ER,4) reads as nothing: a gap.
std::optional<Reading> reading(const Sample& sample) {
  switch (sample.kind) {
    case SampleKind::uls_averaging:
      if (sample.distance_m) return Reading{&distance, *sample.distance_m, metre_decimals};
      return std::nullopt;
    case SampleKind::uls_binning: {
      if (sample.targets.empty()) return std::nullopt;
      const auto nearest =
          std::min_element(sample.targets.begin(), sample.targets.end(),
                           [](const TargetHit& a, const TargetHit& b) { return a.distance_m < b.distance_m; });
      return Reading{&targets, nearest->distance_m, metre_decimals};
    }
    case SampleKind::uls_look_down:
      if (sample.presence) return Reading{&presence, *sample.presence ? 1.0 : 0.0, 0};
      return std::nullopt;
    default:
      return std::nullopt;
  }
}

// ±4 cm typical for a non-cooperative target in every mode, in 1 mm steps (§9); a target at
// 25 m/s (90 km/h, a vehicle passing the unit) crosses a tenth of the 266 m white-wall range a second.
constexpr DistanceScale distance_scale{.accuracy_m = 0.04, .resolution_m = 0.001, .max_speed_mps = 25.0};

// Averaging alone is judged: binning targets come and go, look down and errors carry no distance.
std::optional<QualityInput> quality(const Sample& sample) {
  if (sample.kind != SampleKind::uls_averaging) return std::nullopt;
  QualityInput input{.distance_m = sample.distance_m, .scale = distance_scale, .pulse_width_ps = std::nullopt};
  if (sample.pulse_width) input.pulse_width_ps = static_cast<double>(*sample.pulse_width);
  return input;
}

// A unit address is one byte (0x30-0xEF, §8 RS485 Protocol): its character, or hex.
std::string unit_address_text(int address) {
  if (address < 0 || address > 0xFF) return std::to_string(address);
  return address_text(static_cast<std::uint8_t>(address));
}

constexpr FamilyDescriptor descriptor{
    .name = "uls",
    .title = "LTI Universal Laser Sensor",
    .channels = channels,
    .reading = reading,
    .quality = quality,
    .program_log = make_interface_log_writer,
    .error_text = error_text,
    .address_text = unit_address_text,
};

}  // namespace

const FamilyDescriptor& family() noexcept { return descriptor; }

}  // namespace rangekit::uls
