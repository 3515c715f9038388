#include "rangekit/uls/family.hpp"

#include <algorithm>
#include <array>
#include <cinttypes>

#include "rangekit/core/text.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/formulas.hpp"
#include "rangekit/uls/interface_log.hpp"

namespace rangekit::uls {
namespace {

using text::append_printf;

// Metres with the stream's 4 decimals: 1 mm, and 0.01 ft (3.048 mm) in feet (§9).
constexpr int metre_decimals = 4;

constexpr std::array channels{
    ChannelDescriptor{.key = "distance_m",
                      .quantity = Quantity::distance,
                      .unit = Unit::metre,
                      .description = "averaged distance (averaging mode)",
                      .decimals = metre_decimals,
                      .capture = {"distance_m", ColumnType::real}},
    ChannelDescriptor{.key = "pulse_width_ns",
                      .quantity = Quantity::pulse_width,
                      .unit = Unit::nanosecond,
                      .description = "width of the returned pulse (picoseconds on the wire)",
                      .decimals = 3,
                      .capture = {"pulse_width", ColumnType::integer, 1000}},
    ChannelDescriptor{.key = "targets",
                      .quantity = Quantity::distance,
                      .unit = Unit::metre,
                      .description = "the targets of one binning burst, nearest first",
                      .form = ChannelForm::targets,
                      .decimals = metre_decimals,
                      .capture = {"targets", ColumnType::text}},
    ChannelDescriptor{.key = "presence",
                      .quantity = Quantity::presence,
                      .unit = Unit::none,
                      .description = "look down: 1 a target is there, 0 it left",
                      .form = ChannelForm::flag,
                      .capture = {"presence", ColumnType::integer}},
    ChannelDescriptor{.key = "pulses_between_events",
                      .quantity = Quantity::pulse_count,
                      .unit = Unit::none,
                      .description = "look down: laser pulses between the last two edges",
                      .capture = {"pulses_between_events", ColumnType::integer}},
    ChannelDescriptor{.key = "pulses_overflow",
                      .quantity = Quantity::overflow,
                      .unit = Unit::none,
                      .description = "look down: more than 65535 pulses between the edges",
                      .form = ChannelForm::flag,
                      .capture = {"pulses_overflow", ColumnType::integer},
                      .otherwise = 0.0},
    ChannelDescriptor{.key = "error",
                      .quantity = Quantity::error_number,
                      .unit = Unit::none,
                      .description = "the error number the unit sent",
                      .capture = {"device_error", ColumnType::integer}},
};
static_assert(channels[channel::distance_m.index].key == "distance_m");
static_assert(channels[channel::pulse_width_ns.index].key == "pulse_width_ns");
static_assert(channels[channel::targets].key == "targets");
static_assert(channels[channel::presence.index].key == "presence");
static_assert(channels[channel::pulses_between_events.index].key == "pulses_between_events");
static_assert(channels[channel::pulses_overflow.index].key == "pulses_overflow");
static_assert(channels[channel::error.index].key == "error");

constexpr std::array<std::uint8_t, 2> averaging_channels{channel::distance_m.index, channel::pulse_width_ns.index};
constexpr std::array<std::uint8_t, 1> binning_channels{channel::targets};
constexpr std::array<std::uint8_t, 3> look_down_channels{channel::presence.index, channel::pulses_between_events.index,
                                                         channel::pulses_overflow.index};
constexpr std::array<std::uint8_t, 1> error_channels{channel::error.index};

// Captures written before the kind took the mode's spelling (mode=look-down) say "look_down".
constexpr std::array kinds{
    KindDescriptor{"averaging", averaging_channels},
    KindDescriptor{"binning", binning_channels},
    KindDescriptor{"look-down", look_down_channels, "look_down"},
    KindDescriptor{"error", error_channels},
};
static_assert(kinds[static_cast<std::size_t>(kind::look_down)].name == "look-down");
static_assert(kinds[static_cast<std::size_t>(kind::error)].name == "error");

const ChannelDescriptor& distance = channels[channel::distance_m.index];
const ChannelDescriptor& targets = channels[channel::targets];
const ChannelDescriptor& presence = channels[channel::presence.index];

// Averaging: its distance. Binning: the nearest target, the Interface Program's "first target
// the laser sees" (§2 Display/Target Selection). Look down: the edge, 1 or 0. A §10 error
// (a burst with no target, $ER,4) reads as nothing: a gap.
std::optional<Reading> reading(const Sample& sample) {
  if (sample.kind == kind::averaging) {
    if (const auto metres = sample.get(channel::distance_m)) return Reading{&distance, *metres, metre_decimals};
  } else if (sample.kind == kind::binning) {
    if (sample.targets.empty()) return std::nullopt;
    const auto nearest =
        std::min_element(sample.targets.begin(), sample.targets.end(),
                         [](const TargetHit& a, const TargetHit& b) { return a.distance_m < b.distance_m; });
    return Reading{&targets, nearest->distance_m, metre_decimals};
  } else if (sample.kind == kind::look_down) {
    if (const auto present = sample.get(channel::presence)) return Reading{&presence, *present ? 1.0 : 0.0, 0};
  }
  return std::nullopt;
}

// ±4 cm typical for a non-cooperative target in every mode, in 1 mm steps (§9); a target at
// 25 m/s (90 km/h, a vehicle passing the unit) crosses a tenth of the 266 m white-wall range a second.
constexpr DistanceScale distance_scale{.accuracy_m = 0.04, .resolution_m = 0.001, .max_speed_mps = 25.0};

// Averaging alone is judged: binning targets come and go, look down and errors carry no distance.
std::optional<QualityInput> quality(const Sample& sample) {
  if (sample.kind != kind::averaging) return std::nullopt;
  QualityInput input{.distance_m = sample.get(channel::distance_m), .scale = distance_scale, .pulse_width_ps = {}};
  if (const auto width = sample.get(channel::pulse_width_ns)) input.pulse_width_ps = *width * 1000.0;
  return input;
}

// A unit address is one byte (0x30-0xEF, §8 RS485 Protocol): its character, or hex.
std::string unit_address_text(int address) {
  if (address < 0 || address > 0xFF) return std::to_string(address);
  return address_text(static_cast<std::uint8_t>(address));
}

void append_text(std::string& out, const Sample& sample) {
  if (sample.kind == kind::averaging) {
    if (const auto metres = sample.get(channel::distance_m)) append_printf(out, "  %.3f m", *metres);
    // Picoseconds on the wire (U8), shown in ns with its unit (U92).
    if (const auto width = sample.get(channel::pulse_width_ns)) append_printf(out, "  pw %.3f ns", *width);
  } else if (sample.kind == kind::binning) {
    if (sample.targets.empty()) out += "  no targets";
    for (const auto& target : sample.targets) {
      append_printf(out, "  %.3f m (%" PRIu32 ")", target.distance_m, target.strength);
    }
  } else if (sample.kind == kind::look_down) {
    if (const auto present = sample.get(channel::presence)) out += *present ? "  present" : "  absent";
    if (const auto pulses = sample.get(channel::pulses_between_events)) {
      append_printf(out, "  pulses %" PRIu32, *pulses);
    }
    if (sample.get(channel::pulses_overflow).value_or(false)) out += "  pulses >65535";
  } else if (sample.kind == kind::error) {
    out += "  error";
    if (const auto number = sample.get(channel::error)) {
      append_printf(out, " %d: ", *number);
      out += error_text(*number);  // §10's words (U90)
    }
  }
}

// Captures before the overflow had its column kept it as the wire's 0000 (no real count is 0:
// an edge takes 30 pulses, §3).
void read_back(Sample& sample) {
  if (sample.kind != kind::look_down) return;
  if (sample.get(channel::pulses_between_events) == 0U) {
    sample.set(channel::pulses_between_events, std::nullopt);
    sample.set(channel::pulses_overflow, true);
  }
}

constexpr FamilyDescriptor descriptor{
    .name = "uls",
    .title = "LTI Universal Laser Sensor",
    .channels = channels,
    .kinds = kinds,
    .reading = reading,
    .quality = quality,
    .program_log = make_interface_log_writer,
    .error_text = error_text,
    .address_text = unit_address_text,
    .append_text = append_text,
    .read_back = read_back,
};

static_assert(channel::distance_m.family == descriptor.name, "the channel keys name the family");

}  // namespace

const FamilyDescriptor& family() noexcept { return descriptor; }

}  // namespace rangekit::uls
