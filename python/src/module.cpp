// `_rangekit`: the compiled half of the rangekit Python package. The Python half
// (python/rangekit) gives it the names users import: one module per family, capture, ...
#include "common.hpp"
#include "python_family.hpp"
#include "rangekit/version.hpp"

PYBIND11_MODULE(_rangekit, module) {
  module.doc() = "rangekit's C++ library for Python; import rangekit, not this module";
  module.attr("version") = std::string(rangekit::version_string);
  rangekit::python::init_samples(module);
  rangekit::python::init_streams(module);
  rangekit::python::init_families(module);
  for (const rangekit::python::PythonFamily* family : rangekit::python::python_families()) family->bind(module);
  rangekit::python::init_capture(module);
}
