#include "rangekit/core/family.hpp"

#include <algorithm>
#include <vector>

namespace rangekit {
namespace {

// A handful of families at most: a vector searched by name beats a map, and its order is
// the registration order faces list families in.
std::vector<const FamilyDescriptor*>& registry() {
  static std::vector<const FamilyDescriptor*> families;
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
    case Unit::picosecond:
      return "ps";
  }
  return "";
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
  auto& families = registry();
  const auto same_name = std::find_if(families.begin(), families.end(),
                                      [&](const FamilyDescriptor* known) { return known->name == family.name; });
  if (same_name != families.end()) {
    *same_name = &family;
  } else {
    families.push_back(&family);
  }
}

std::span<const FamilyDescriptor* const> families() noexcept { return registry(); }

const FamilyDescriptor* find_family(std::string_view name) noexcept {
  for (const FamilyDescriptor* family : registry()) {
    if (family->name == name) return family;
  }
  return nullptr;
}

const ChannelDescriptor* find_channel(const FamilyDescriptor& family, std::string_view key) noexcept {
  for (const ChannelDescriptor& channel : family.channels) {
    if (channel.key == key) return &channel;
  }
  return nullptr;
}

std::optional<Reading> reading_of(const Sample& sample) {
  const FamilyDescriptor* family = find_family(sample.device);
  if (family == nullptr || family->reading == nullptr) return std::nullopt;
  return family->reading(sample);
}

std::string error_text_of(const Sample& sample, int number) {
  const FamilyDescriptor* family = find_family(sample.device);
  if (family == nullptr || family->error_text == nullptr) return {};
  return family->error_text(number);
}

}  // namespace rangekit
