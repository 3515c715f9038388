// The LS5 fields of rangekit.Sample and of the NumPy record: the result code (§9.3) and the
// distance or derivative it gives.
#include <string>

#include "ls5/parts.hpp"
#include "rangekit/ls5/family.hpp"

namespace rangekit::ls5::python {

using namespace rangekit::python;  // the module's shared helpers: py, optional_object, flag, ...

void sample_properties(py::class_<Sample>& sample_class) {
  sample_class
      .def_property_readonly(
          "code", [](const Sample& s) { return optional_object(s.get(channel::code)); },
          "LS5 result code 0-65535 (§9.3), or None")
      .def_property_readonly(
          "distance_mm", [](const Sample& s) { return optional_object(s.get(channel::distance_mm)); },
          "LS5 distance in millimetres (formula 8.1), None for 65534/65535")
      .def_property_readonly(
          "derivative_mm", [](const Sample& s) { return optional_object(s.get(channel::derivative_mm)); },
          "LS5 distance derivative in millimetres (formula 8.2), or None")
      .def_property_readonly(
          "signal",
          [](const Sample& s) {
            return s.get(channel::signal) ? py::cast(std::string(signal_state_name(*s.get(channel::signal))))
                                          : py::none();
          },
          "LS5: 'ok', 'none_yet' (65534) or 'lost' (65535), or None")
      .def_property_readonly(
          "resolution_mm", [](const Sample& s) { return optional_object(s.get(channel::resolution_mm)); },
          "LS5: the sensor's discreteness in millimetres (table 3.1), or None");
}

void fill_record(const Sample& sample, SampleRecord& record) noexcept {
  record.code = sample.get(channel::code).value_or(0);
  if (sample.get(channel::signal) == SignalState::lost) record.flags |= flag::no_signal;          // 65535
  if (sample.get(channel::signal) == SignalState::none_yet) record.flags |= flag::no_result_yet;  // 65534
  if (sample.kind == kind::derivative) record.flags |= flag::derivative;
}

std::string describe(const Sample& sample) {
  std::string text;
  if (const auto millimetres = sample.get(channel::distance_mm)) text += " distance_mm=" + std::to_string(*millimetres);
  if (const auto code = sample.get(channel::code)) text += " code=" + std::to_string(*code);
  return text;
}

}  // namespace rangekit::ls5::python
