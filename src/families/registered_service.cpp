// Registers every family's part of the sensor service (hub/service_family.hpp) before main():
// linked as an object into the CLI and the tests, which run the service.
#include "families/list.hpp"
#include "rangekit/hub/service_family.hpp"

#define RANGEKIT_DECLARE(name)                                                                         \
  namespace rangekit::name::service {                                                                  \
  const hub::ServiceFamily& service_family() noexcept; /* NOLINT(readability-redundant-declaration) */ \
  }
RANGEKIT_FAMILIES(RANGEKIT_DECLARE)
#undef RANGEKIT_DECLARE

namespace {

const bool registered = [] {
#define RANGEKIT_REGISTER(name) rangekit::hub::register_service_family(rangekit::name::service::service_family());
  RANGEKIT_FAMILIES(RANGEKIT_REGISTER)
#undef RANGEKIT_REGISTER
  return true;
}();

}  // namespace
