// Registers every family's channels and readings (core/family.hpp) before main(): linked as an
// object into each program, so the linker cannot leave it out.
#include "families/list.hpp"
#include "rangekit/core/family.hpp"

#define RANGEKIT_DECLARE(name)                                                               \
  namespace rangekit::name {                                                                 \
  const FamilyDescriptor& family() noexcept; /* NOLINT(readability-redundant-declaration) */ \
  }
RANGEKIT_FAMILIES(RANGEKIT_DECLARE)
#undef RANGEKIT_DECLARE

namespace {

const bool registered = [] {
#define RANGEKIT_REGISTER(name) rangekit::register_family(rangekit::name::family());
  RANGEKIT_FAMILIES(RANGEKIT_REGISTER)
#undef RANGEKIT_REGISTER
  return true;
}();

}  // namespace
