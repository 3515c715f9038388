#include "targets_text.hpp"

#include <nlohmann/json.hpp>

namespace rangekit::record {

void parse_targets_text(std::string_view text, TargetList& targets) {
  const auto array = nlohmann::json::parse(text, nullptr, false);
  if (!array.is_array()) return;
  for (const auto& entry : array) {
    if (!entry.is_object()) continue;
    TargetHit target;
    if (const auto distance = entry.find("distance_m"); distance != entry.end() && distance->is_number()) {
      target.distance_m = distance->get<double>();
    }
    if (const auto strength = entry.find("strength"); strength != entry.end() && strength->is_number_unsigned()) {
      target.strength = strength->get<std::uint32_t>();
    }
    targets.push_back(target);
  }
}

}  // namespace rangekit::record
