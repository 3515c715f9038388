#include "rangekit/core/family.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "rangekit/core/registry.hpp"

namespace rangekit {
namespace {

Registry<FamilyDescriptor>& registry() {
  static Registry<FamilyDescriptor> families;
  return families;
}

}  // namespace

const char* quantity_name(Quantity quantity) noexcept {
  switch (quantity) {
    case Quantity::distance:
      return "distance";
    case Quantity::distance_change:
      return "distance_change";
    case Quantity::pulse_width:
      return "pulse_width";
    case Quantity::strength:
      return "strength";
    case Quantity::presence:
      return "presence";
    case Quantity::pulse_count:
      return "pulse_count";
    case Quantity::result_code:
      return "result_code";
    case Quantity::error_number:
      return "error_number";
    case Quantity::signal:
      return "signal";
    case Quantity::overflow:
      return "overflow";
    case Quantity::resolution:
      return "resolution";
  }
  return "unknown";
}

const char* unit_symbol(Unit unit) noexcept {
  switch (unit) {
    case Unit::none:
      return "";
    case Unit::metre:
      return "m";
    case Unit::millimetre:
      return "mm";
    case Unit::nanosecond:
      return "ns";
  }
  return "";
}

int decimals_of_step(double step) noexcept {
  if (!std::isfinite(step) || step <= 0) return -1;
  // Every reading of a stream asks with its sensor's one step: the last answer is kept per
  // thread, as a log10 a reading for each client was a visible part of a busy service.
  thread_local double last_step = 0;
  thread_local int last_decimals = -1;
  if (step == last_step) return last_decimals;
  const double digits = std::ceil(-std::log10(step) - 1e-9);
  last_step = step;
  last_decimals = std::clamp(static_cast<int>(digits), 0, 9);
  return last_decimals;
}

// Through the text a stream prints ("%.4f"), so a figure and a sample of the same value
// read the same: 24.845 with 2 decimals is 24.84 in both (it is 24.84499... in binary).
double rounded_to(double value, int decimals) noexcept {
  if (decimals < 0 || !std::isfinite(value)) return value;
  std::array<char, 352> text{};  // the longest fixed text of a double, 9 decimals
  const auto written = std::to_chars(text.data(), text.data() + text.size(), value, std::chars_format::fixed, decimals);
  if (written.ec != std::errc{}) return value;
  double rounded = value;
  std::from_chars(text.data(), written.ptr, rounded);
  return rounded;
}

std::optional<double> metres_per(Unit unit) noexcept {
  switch (unit) {
    case Unit::metre:
      return 1.0;
    case Unit::millimetre:
      return 0.001;
    default:
      return std::nullopt;
  }
}

void register_family(const FamilyDescriptor& family) {
  // A channel beyond the sample's capacity could not be kept: a mistake in the family's table.
  if (family.channels.size() > ChannelValues::capacity) std::abort();
  registry().add(family);
}

std::span<const FamilyDescriptor* const> families() noexcept { return registry().all(); }

const FamilyDescriptor* find_family(std::string_view name) noexcept { return registry().find(name); }

const ChannelDescriptor* find_channel(const FamilyDescriptor& family, std::string_view key) noexcept {
  const auto index = channel_index(family, key);
  return index ? &family.channels[*index] : nullptr;
}

std::optional<std::size_t> channel_index(const FamilyDescriptor& family, std::string_view key) noexcept {
  for (std::size_t index = 0; index < family.channels.size(); ++index) {
    if (family.channels[index].key == key) return index;
  }
  return std::nullopt;
}

std::optional<std::size_t> channel_index(const FamilyDescriptor& family, Quantity quantity) noexcept {
  for (std::size_t index = 0; index < family.channels.size(); ++index) {
    if (family.channels[index].quantity == quantity) return index;
  }
  return std::nullopt;
}

int channel_decimals(const ChannelDescriptor& channel, const Sample& sample) noexcept {
  if (channel.step_channel >= 0) {
    if (const auto step = sample.values.get(static_cast<std::size_t>(channel.step_channel))) {
      const int decimals = decimals_of_step(*step);
      if (decimals >= 0) return std::min(decimals, 6);
    }
  }
  return channel.decimals;
}

const FamilyDescriptor* family_of(const Sample& sample) noexcept {
  for (const FamilyDescriptor* family : families()) {
    if (sample.is_of(family->name)) return family;
  }
  return nullptr;
}

const KindDescriptor* kind_of(const FamilyDescriptor* family, const Sample& sample) noexcept {
  const auto index = static_cast<std::size_t>(sample.kind);
  if (family == nullptr || index >= family->kinds.size()) return nullptr;
  return &family->kinds[index];
}

const KindDescriptor* kind_of(const Sample& sample) noexcept { return kind_of(family_of(sample), sample); }

std::string_view kind_name_of(const KindDescriptor* kind) noexcept {
  return kind != nullptr ? kind->name : std::string_view("unknown");
}

std::string_view kind_name_of(const Sample& sample) noexcept { return kind_name_of(kind_of(sample)); }

std::optional<SampleKind> find_kind(const FamilyDescriptor& family, std::string_view name) noexcept {
  for (std::size_t index = 0; index < family.kinds.size(); ++index) {
    const KindDescriptor& kind = family.kinds[index];
    if (name == kind.name || (!kind.former_name.empty() && name == kind.former_name)) {
      return static_cast<SampleKind>(index);
    }
  }
  return std::nullopt;
}

std::optional<double> value_of(const Sample& sample, Quantity quantity) noexcept {
  const FamilyDescriptor* family = family_of(sample);
  if (family == nullptr) return std::nullopt;
  const auto index = channel_index(*family, quantity);
  return index ? sample.values.get(*index) : std::nullopt;
}

bool signal_lost(const Sample& sample) noexcept {
  const FamilyDescriptor* family = family_of(sample);
  if (family == nullptr) return false;
  const auto index = channel_index(*family, Quantity::signal);
  if (!index) return false;
  const std::size_t states = family->channels[*index].states.size();
  return states >= 2 && sample.values.get(*index) == static_cast<double>(states - 1);
}

std::optional<Reading> reading_of(const Sample& sample) {
  const FamilyDescriptor* family = family_of(sample);
  if (family == nullptr || family->reading == nullptr) return std::nullopt;
  return family->reading(sample);
}

std::optional<QualityInput> quality_input_of(const Sample& sample) {
  const FamilyDescriptor* family = family_of(sample);
  if (family == nullptr || family->quality == nullptr) return std::nullopt;
  return family->quality(sample);
}

std::string error_text_of(std::string_view family_name, int number) {
  const FamilyDescriptor* family = find_family(family_name);
  if (family == nullptr || family->error_text == nullptr) return {};
  return family->error_text(number);
}

std::string error_text_of(const Sample& sample, int number) { return error_text_of(sample.device, number); }

std::string address_text_of(std::string_view family_name, int address) {
  const FamilyDescriptor* family = find_family(family_name);
  if (family == nullptr || family->address_text == nullptr) return std::to_string(address);
  return family->address_text(address);
}

}  // namespace rangekit
