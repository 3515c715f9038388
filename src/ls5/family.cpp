#include "rangekit/ls5/family.hpp"

#include <array>
#include <cmath>

#include "rangekit/core/text.hpp"
#include "rangekit/ls5/result_code.hpp"

namespace rangekit::ls5 {
namespace {

using text::append_printf;

// How captures without the discreteness printed their millimetres.
constexpr int default_decimals = 2;

constexpr std::array<std::string_view, 3> signal_states{"ok", "none_yet", "lost"};

constexpr std::array channels{
    ChannelDescriptor{.key = "code",
                      .quantity = Quantity::result_code,
                      .unit = Unit::none,
                      .description = "the result code as sent, 0 to 65535",
                      .capture = {"code", ColumnType::integer}},
    ChannelDescriptor{.key = "distance_mm",
                      .quantity = Quantity::distance,
                      .unit = Unit::millimetre,
                      .description = "distance within the measuring range",
                      .decimals = default_decimals,
                      .step_channel = channel::resolution_mm.index,
                      .capture = {"distance_mm", ColumnType::real}},
    ChannelDescriptor{.key = "signal",
                      .quantity = Quantity::signal,
                      .unit = Unit::none,
                      .description = "ok, none_yet (code 65534) or lost (code 65535)",
                      .form = ChannelForm::state,
                      .states = signal_states,
                      .capture = {"signal", ColumnType::text}},
    ChannelDescriptor{.key = "derivative_mm",
                      .quantity = Quantity::distance_change,
                      .unit = Unit::millimetre,
                      .description = "difference of two results (a derivative)",
                      .decimals = default_decimals,
                      .step_channel = channel::resolution_mm.index,
                      .capture = {"derivative_mm", ColumnType::real}},
    ChannelDescriptor{.key = "resolution_mm",
                      .quantity = Quantity::resolution,
                      .unit = Unit::millimetre,
                      .description = "the sensor's discreteness at its range (table 3.1)",
                      .capture = {"resolution_mm", ColumnType::real},
                      .in_stream = false},
};
static_assert(channels[channel::code.index].key == "code");
static_assert(channels[channel::distance_mm.index].key == "distance_mm");
static_assert(channels[channel::signal.index].key == "signal");
static_assert(channels[channel::derivative_mm.index].key == "derivative_mm");
static_assert(channels[channel::resolution_mm.index].key == "resolution_mm");

constexpr std::array<std::uint8_t, 3> result_channels{channel::code.index, channel::distance_mm.index,
                                                      channel::signal.index};
constexpr std::array<std::uint8_t, 3> derivative_channels{channel::code.index, channel::derivative_mm.index,
                                                          channel::signal.index};
constexpr std::array kinds{
    KindDescriptor{"result", result_channels},
    KindDescriptor{"derivative", derivative_channels},
};
static_assert(kinds[static_cast<std::size_t>(kind::derivative)].name == "derivative");

const ChannelDescriptor& distance = channels[channel::distance_mm.index];
const ChannelDescriptor& derivative = channels[channel::derivative_mm.index];

// A result: its distance; a derivative: the change. 65534 and 65535 (§9.3) carry neither.
std::optional<Reading> reading(const Sample& sample) {
  if (sample.get(channel::signal).value_or(SignalState::ok) != SignalState::ok) return std::nullopt;
  const bool is_derivative = sample.kind == kind::derivative;
  const auto value = sample.get(is_derivative ? channel::derivative_mm : channel::distance_mm);
  if (!value) return std::nullopt;
  const auto step = sample.get(channel::resolution_mm);
  return Reading{is_derivative ? &derivative : &distance, *value, step ? decimals_of_step(*step) : default_decimals};
}

// Results alone are judged, on the scale their own code shows: ±0.15 % of the range (table 3.1),
// one code a 50000th of it (formula 8.1), and a target crossing the whole range in a second.
std::optional<QualityInput> quality(const Sample& sample) {
  if (sample.kind != kind::result) return std::nullopt;
  QualityInput input;
  if (const auto millimetres = sample.get(channel::distance_mm)) input.distance_m = *millimetres / 1000.0;
  if (const auto range = range_from_result_mm(sample)) {
    const double range_m = *range / 1000.0;
    input.scale = DistanceScale{
        .accuracy_m = 0.0015 * range_m, .resolution_m = range_m / max_result_code, .max_speed_mps = range_m};
  }
  return input;
}

void append_text(std::string& out, const Sample& sample) {
  const bool is_derivative = sample.kind == kind::derivative;
  if (is_derivative) out += "  derivative";
  const auto signal = sample.get(channel::signal);
  if (const auto value = sample.get(is_derivative ? channel::derivative_mm : channel::distance_mm)) {
    // As many decimals as the sensor's discreteness has (0.0001 mm: 4, 0.1 mm: 1; table 3.1, L63).
    append_printf(out, is_derivative ? " %+.*f mm" : "  %.*f mm",
                  channel_decimals(is_derivative ? derivative : distance, sample), *value);
  } else if (signal == SignalState::none_yet) {
    out += "  no measurement yet";
  } else if (signal == SignalState::lost) {
    out += "  no signal";
  }
  if (const auto code = sample.get(channel::code)) append_printf(out, "  code %u", static_cast<unsigned>(*code));
}

constexpr FamilyDescriptor descriptor{
    .name = "ls5",
    .title = "Prizma LS5 laser triangulation sensor",
    .channels = channels,
    .kinds = kinds,
    .reading = reading,
    .quality = quality,
    .append_text = append_text,
};

static_assert(channel::code.family == descriptor.name, "the channel keys name the family");

}  // namespace

const char* signal_state_name(SignalState state) noexcept {
  const auto index = static_cast<std::size_t>(state);
  return index < signal_states.size() ? signal_states[index].data() : "unknown";
}

std::optional<double> range_from_result_mm(const Sample& sample) noexcept {
  const auto code = sample.get(channel::code);
  const auto millimetres = sample.get(channel::distance_mm);
  if (!code || *code == 0 || !millimetres || !std::isfinite(*millimetres)) return std::nullopt;
  return *millimetres * max_result_code / *code;
}

const FamilyDescriptor& family() noexcept { return descriptor; }

}  // namespace rangekit::ls5
