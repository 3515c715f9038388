// Registers every family's part of the rangekit binary (cli/cli_family.hpp) before main():
// compiled into the binary, which alone links CLI11.
#include "cli/cli_family.hpp"
#include "families/list.hpp"

#define RANGEKIT_DECLARE(name)                                                                 \
  namespace rangekit::name {                                                                   \
  const cli::CliFamily& cli_family() noexcept; /* NOLINT(readability-redundant-declaration) */ \
  }
RANGEKIT_FAMILIES(RANGEKIT_DECLARE)
#undef RANGEKIT_DECLARE

namespace {

const bool registered = [] {
#define RANGEKIT_REGISTER(name) rangekit::cli::register_cli_family(rangekit::name::cli_family());
  RANGEKIT_FAMILIES(RANGEKIT_REGISTER)
#undef RANGEKIT_REGISTER
  return true;
}();

}  // namespace
