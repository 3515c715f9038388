// Every family's part of the Python module (python_family.hpp), from the registration list:
// the shared part reaches the families through here only.
#include <algorithm>
#include <array>

#include "families/list.hpp"
#include "python_family.hpp"

#define RANGEKIT_DECLARE(name)                                                                      \
  namespace rangekit::name::python {                                                                \
  const rangekit::python::PythonFamily& python_family() noexcept; /* defined in python/src/name/ */ \
  }
RANGEKIT_FAMILIES(RANGEKIT_DECLARE)
#undef RANGEKIT_DECLARE

namespace rangekit::python {

std::span<const PythonFamily* const> python_families() noexcept {
#define RANGEKIT_ENTRY(name) &rangekit::name::python::python_family(),
  static const std::array all{RANGEKIT_FAMILIES(RANGEKIT_ENTRY)};
#undef RANGEKIT_ENTRY
  return all;
}

const PythonFamily* find_python_family(std::string_view name) noexcept {
  const auto all = python_families();
  const auto found =
      std::find_if(all.begin(), all.end(), [&](const PythonFamily* family) { return family->name == name; });
  return found == all.end() ? nullptr : *found;
}

}  // namespace rangekit::python
