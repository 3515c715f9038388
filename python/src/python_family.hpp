// A family's part of the Python module: its submodule and the fields it adds to the shared
// rangekit.Sample and NumPy record. Each family fills one in python/src/<family>/, and
// registered_families.cpp lists them all from the registration list (families.cmake).
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "common.hpp"

namespace rangekit::python {

struct PythonFamily {
  std::string_view name;  // its FamilyDescriptor's name: the submodule, a sample's `device`
  // Defines the submodule `name` (driver, codec) under `parent`.
  void (*bind)(py::module_& parent) = nullptr;
  // The hooks below may be null: the family adds nothing there.
  // Adds the properties of the family's fields of rangekit::Sample to rangekit.Sample; they
  // read None (or empty) on another family's samples.
  void (*sample_properties)(py::class_<Sample>& sample_class) = nullptr;
  // Fills the record's columns and flags that only the family's samples carry.
  void (*fill_record)(const Sample& sample, SampleRecord& record) noexcept = nullptr;
  // What repr() shows after the kind: " distance_m=12.345000 device_error=4".
  std::string (*describe)(const Sample& sample) = nullptr;
};

// Every family's part, in the order of the registration list.
std::span<const PythonFamily* const> python_families() noexcept;
const PythonFamily* find_python_family(std::string_view name) noexcept;

}  // namespace rangekit::python
