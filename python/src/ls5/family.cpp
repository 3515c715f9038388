// The LS5 part of the Python module, as registered_families.cpp lists it.
#include "ls5/parts.hpp"

namespace rangekit::ls5::python {

const rangekit::python::PythonFamily& python_family() noexcept {
  static constexpr rangekit::python::PythonFamily part{
      .name = "ls5",
      .bind = bind,
      .sample_properties = sample_properties,
      .fill_record = fill_record,
      .describe = describe,
  };
  return part;
}

}  // namespace rangekit::ls5::python
