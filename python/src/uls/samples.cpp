// The ULS fields of rangekit.Sample and of the NumPy record: averaging, binning, look down
// and the §10 error number.
#include <string>

#include "rangekit/core/family.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/family.hpp"
#include "uls/parts.hpp"

namespace rangekit::uls::python {

using namespace rangekit::python;  // the module's shared helpers: py, optional_object, flag, ...

void sample_properties(py::class_<Sample>& sample_class) {
  sample_class
      .def_property_readonly(
          "distance_m", [](const Sample& s) { return optional_object(s.get(channel::distance_m)); },
          "ULS averaging distance in metres, or None")
      .def_property_readonly(
          "pulse_width_ns",
          [](const Sample& s) {
            return s.get(channel::pulse_width_ps)
                       ? py::cast(static_cast<double>(*s.get(channel::pulse_width_ps)) / 1000.0)
                       : py::none();
          },
          "ULS pulse width in nanoseconds (the wire's integer picoseconds / 1000), or None")
      .def_property_readonly(
          "targets",
          [](const Sample& s) {
            py::list targets;
            for (const TargetHit& hit : s.targets) targets.append(py::make_tuple(hit.distance_m, hit.strength));
            return targets;
          },
          "ULS binning: [(distance_m, strength), ...], strength in hits of the target's bin")
      .def_property_readonly(
          "presence", [](const Sample& s) { return optional_object(s.get(channel::presence)); },
          "ULS look down: a target present, or None")
      .def_property_readonly(
          "pulses_between_events",
          [](const Sample& s) { return optional_object(s.get(channel::pulses_between_events)); },
          "ULS look down with TB: pulses between the edges (1-65535), or None")
      .def_property_readonly(
          "pulses_overflow", [](const Sample& s) { return s.get(channel::pulses_overflow).value_or(false); },
          "ULS look down: more than 65535 pulses (U88)")
      .def_property_readonly(
          "device_error", [](const Sample& s) { return optional_object(s.get(channel::error)); },
          "ULS $ER,n error number (§10), or None")
      .def_property_readonly(
          "error_text",
          [](const Sample& s) {
            return s.get(channel::error) ? py::cast(error_text_of(s, *s.get(channel::error))) : py::none();
          },
          "the §10 text of device_error, or None");
}

void fill_record(const Sample& sample, SampleRecord& record) noexcept {
  if (sample.get(channel::pulse_width_ps)) {
    record.intensity =
        static_cast<double>(*sample.get(channel::pulse_width_ps)) / 1000.0;  // ps on the wire (U8), ns here
  } else if (!sample.targets.empty()) {
    record.intensity = static_cast<double>(sample.targets.front().strength);
  }
  record.targets = static_cast<std::uint8_t>(sample.targets.size());
  record.pulses = sample.get(channel::pulses_between_events).value_or(0);
  if (sample.get(channel::error)) {
    record.error = static_cast<std::int16_t>(*sample.get(channel::error));
    record.flags |= flag::device_error;
    if (*sample.get(channel::error) == error_number::target_not_found) record.flags |= flag::no_signal;
    if (*sample.get(channel::error) == error_number::average_not_filled) record.flags |= flag::no_result_yet;
  }
  if (sample.get(channel::presence).value_or(false)) record.flags |= flag::presence;
  if (sample.get(channel::pulses_overflow).value_or(false)) record.flags |= flag::pulses_overflow;
}

std::string describe(const Sample& sample) {
  std::string text;
  if (const auto metres = sample.get(channel::distance_m)) text += " distance_m=" + std::to_string(*metres);
  if (const auto number = sample.get(channel::error)) text += " device_error=" + std::to_string(*number);
  return text;
}

}  // namespace rangekit::uls::python
