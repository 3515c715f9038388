// The ULS part of the Python module, as registered_families.cpp lists it.
#include "uls/parts.hpp"

namespace rangekit::uls::python {

const rangekit::python::PythonFamily& python_family() noexcept {
  static constexpr rangekit::python::PythonFamily part{
      .name = "uls",
      .bind = bind,
      .sample_properties = sample_properties,
      .fill_record = fill_record,
      .describe = describe,
  };
  return part;
}

}  // namespace rangekit::uls::python
