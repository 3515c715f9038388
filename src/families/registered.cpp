// The registration list: the one place that names every family. A program or test that
// links this object has them all registered before main() runs.
#include "rangekit/core/family.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/uls/family.hpp"

namespace {

const bool registered = [] {
  rangekit::register_family(rangekit::uls::family());
  rangekit::register_family(rangekit::ls5::family());
  return true;
}();

}  // namespace
