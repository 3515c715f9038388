// The LS5 part of the Python module (python_family.hpp), filled in by this folder's files.
#pragma once

#include <string>

#include "python_family.hpp"

namespace rangekit::ls5::python {

void bind(pybind11::module_& parent);                                                     // bindings.cpp
void sample_properties(pybind11::class_<Sample>& sample_class);                           // samples.cpp
void fill_record(const Sample& sample, rangekit::python::SampleRecord& record) noexcept;  // samples.cpp
std::string describe(const Sample& sample);                                               // samples.cpp
const rangekit::python::PythonFamily& python_family() noexcept;                           // family.cpp

}  // namespace rangekit::ls5::python
