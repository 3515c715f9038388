#include "rangekit/hub/service_family.hpp"

#include "rangekit/core/registry.hpp"

namespace rangekit::hub {
namespace {

Registry<ServiceFamily>& registry() {
  static Registry<ServiceFamily> families;
  return families;
}

}  // namespace

void register_service_family(const ServiceFamily& family) { registry().add(family); }

std::span<const ServiceFamily* const> service_families() noexcept { return registry().all(); }

const ServiceFamily* find_service_family(std::string_view name) noexcept { return registry().find(name); }

std::string service_family_names() {
  std::string names;
  const auto families = service_families();
  for (std::size_t i = 0; i < families.size(); ++i) {
    if (i > 0) names += i + 1 == families.size() ? " or " : ", ";
    names += "\"" + std::string(families[i]->name) + "\"";
  }
  return names;
}

}  // namespace rangekit::hub
