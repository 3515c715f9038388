#include "modbus/unit_state.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "rangekit/core/family.hpp"

namespace rangekit::modbus {
namespace {

constexpr std::int32_t no_micrometres = std::numeric_limits<std::int32_t>::min();

// A distance reading in millimetres; none for a reading of another quantity (look down's presence).
std::optional<double> millimetres_of(const Reading& reading) {
  if (reading.channel == nullptr) return std::nullopt;
  if (reading.channel->quantity != Quantity::distance && reading.channel->quantity != Quantity::distance_change) {
    return std::nullopt;
  }
  const auto metres = metres_per(reading.channel->unit);
  if (!metres) return std::nullopt;
  return reading.value * *metres * 1000.0;
}

void put_u32(InputImage& image, std::uint16_t at, std::uint32_t value, WordOrder order) {
  const auto words = words_of_u32(value, order);
  image[at] = words[0];
  image[at + 1] = words[1];
}

void put_float(InputImage& image, std::uint16_t at, float value, WordOrder order) {
  put_u32(image, at, std::bit_cast<std::uint32_t>(value), order);
}

// Whether the sample's kind has a targets channel (a binning burst): with none in it, it saw nothing.
bool shows_targets(const Sample& sample) {
  const FamilyDescriptor* family = family_of(sample);
  const KindDescriptor* kind = kind_of(family, sample);
  if (kind == nullptr) return false;
  for (std::size_t channel = 0; channel < family->channels.size(); ++channel) {
    if (family->channels[channel].form == ChannelForm::targets && kind->shows(channel)) return true;
  }
  return false;
}

std::uint32_t low32(std::uint64_t count) { return static_cast<std::uint32_t>(count & 0xFFFFFFFFU); }

}  // namespace

void apply_sample(UnitState& state, const Sample& sample, std::chrono::steady_clock::time_point now) {
  state.heard = true;
  ++state.sequence;
  state.arrived = now;
  state.suspect = sample.suspect;
  const auto reading = reading_of(sample);
  state.reading_mm = reading ? millimetres_of(*reading) : std::nullopt;
  std::optional<double> error = value_of(sample, Quantity::error_number);
  if (!error && value_of(sample, Quantity::signal).value_or(0) != 0) error = value_of(sample, Quantity::result_code);
  state.device_error = static_cast<std::uint16_t>(std::clamp(error.value_or(0), 0.0, 65535.0));
  state.target_count = 0;
  if (reading && reading->channel != nullptr && reading->channel->form == ChannelForm::targets) {
    for (const TargetHit& hit : sample.targets) {
      if (state.target_count == input::max_targets) break;
      state.targets_mm[state.target_count++] = static_cast<float>(hit.distance_m * 1000.0);
    }
    std::sort(state.targets_mm.begin(), state.targets_mm.begin() + state.target_count);
  } else if (state.reading_mm) {
    state.targets_mm[0] = static_cast<float>(*state.reading_mm);
    state.target_count = 1;
  }
  const auto presence = value_of(sample, Quantity::presence);
  state.no_target =
      signal_lost(sample) || (presence && *presence == 0) || (sample.targets.empty() && shows_targets(sample));
}

void apply_health(UnitState& state, bool streaming, const hub::SensorHealth& health) {
  state.connected = health.connected;
  state.streaming = streaming;
  state.rate_hz = health.rate_hz;
  state.records = health.records;
  state.errors = health.errors;
  state.lost = health.lost;
}

bool is_stale(const UnitState& state, std::chrono::steady_clock::time_point now) {
  if (!state.heard || !state.connected) return true;
  using seconds = std::chrono::duration<double>;
  const double allowed = state.rate_hz > 0 ? std::max(3.0 / state.rate_hz, 0.1) : 2.0;
  return seconds(now - state.arrived).count() > allowed;
}

InputImage input_registers(const UnitState& state, std::chrono::steady_clock::time_point now, WordOrder order) {
  InputImage image{};
  const bool valid = state.reading_mm.has_value() && state.device_error == 0;
  if (state.reading_mm) {
    put_float(image, input::reading_mm, static_cast<float>(*state.reading_mm), order);
    const double micrometres = std::round(*state.reading_mm * 1000.0);
    const bool fits = micrometres > static_cast<double>(no_micrometres) &&
                      micrometres <= static_cast<double>(std::numeric_limits<std::int32_t>::max());
    put_u32(image, input::reading_um,
            static_cast<std::uint32_t>(fits ? static_cast<std::int32_t>(micrometres) : no_micrometres), order);
  } else {
    put_float(image, input::reading_mm, std::numeric_limits<float>::quiet_NaN(), order);
    put_u32(image, input::reading_um, static_cast<std::uint32_t>(no_micrometres), order);
  }
  unsigned bits = 0;
  if (state.connected) bits |= 1U << status_bit::connected;
  if (state.streaming) bits |= 1U << status_bit::streaming;
  if (valid) bits |= 1U << status_bit::valid;
  if (state.suspect) bits |= 1U << status_bit::suspect;
  if (is_stale(state, now)) bits |= 1U << status_bit::stale;
  if (state.no_target) bits |= 1U << status_bit::no_target;
  image[input::status] = static_cast<std::uint16_t>(bits);
  image[input::device_error] = state.device_error;
  put_u32(image, input::sequence, state.sequence, order);
  if (state.heard) {
    const auto age = std::chrono::duration_cast<std::chrono::milliseconds>(now - state.arrived).count();
    image[input::age_ms] = static_cast<std::uint16_t>(std::clamp<std::int64_t>(age, 0, 65535));
  } else {
    image[input::age_ms] = 65535;
  }
  put_u32(image, input::records, low32(state.records), order);
  put_u32(image, input::errors, low32(state.errors), order);
  put_u32(image, input::lost, low32(state.lost), order);
  image[input::target_count] = state.target_count;
  for (std::uint16_t target = 0; target < state.target_count; ++target) {
    put_float(image, static_cast<std::uint16_t>(input::first_target_mm + 2 * target), state.targets_mm[target], order);
  }
  return image;
}

}  // namespace rangekit::modbus
