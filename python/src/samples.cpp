// Samples and events as Python objects, the NumPy record, and errors as exceptions.
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "common.hpp"
#include "python_family.hpp"
#include "rangekit/core/family.hpp"

namespace rangekit::python {
namespace {

// The rangekit.errors class each error code is raised as (docs/python.md).
const char* exception_name(Errc code) noexcept {
  switch (code) {
    case Errc::device_error:
      return "DeviceError";
    case Errc::out_of_range:
    case Errc::wrong_form:
    case Errc::unknown_command:
    case Errc::unknown_parameter:
    case Errc::bad_number:
    case Errc::bad_hex:
      return "SettingError";
    case Errc::timeout:
      return "NoReply";
    case Errc::io:
    case Errc::closed:
      return "LinkError";
    case Errc::invalid_frame:
    case Errc::truncated:
    case Errc::overlong:
    case Errc::bad_checksum:
      return "DecodeError";
    case Errc::unsupported:
      return "UnsupportedError";
    case Errc::limit:
      return "RangekitError";
  }
  return "RangekitError";
}

// "invalid frame" -> "invalid_frame": a name a Python user compares with.
std::string code_name(Errc code) {
  std::string name = errc_name(code);
  for (char& c : name)
    if (c == ' ') c = '_';
  return name;
}

constexpr double not_a_number = std::numeric_limits<double>::quiet_NaN();

}  // namespace

void raise_error(const Error& error, std::string_view family) {
  py::object errors = py::module_::import("rangekit.errors");
  py::object number = py::none();
  py::object text = py::none();
  if (error.code == Errc::device_error) {
    number = py::int_(error.device_code);
    if (const std::string words = error_text_of(family, error.device_code); !words.empty()) text = py::str(words);
  }
  py::object exception = errors.attr(exception_name(error.code))(error.message, code_name(error.code), number, text);
  PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(exception.ptr())), exception.ptr());
  throw py::error_already_set();
}

double to_seconds(std::chrono::system_clock::time_point time) noexcept {
  return std::chrono::duration<double>(time.time_since_epoch()).count();
}

// The sample's kind among every family's kinds (rangekit.sample_kinds); 255 for one not registered.
std::uint8_t kind_number(const FamilyDescriptor* family, const Sample& sample) {
  std::size_t number = 0;
  for (const FamilyDescriptor* registered : families()) {
    if (registered == family) {
      const auto kind = static_cast<std::size_t>(sample.kind);
      return kind < family->kinds.size() ? static_cast<std::uint8_t>(number + kind) : 255;
    }
    number += registered->kinds.size();
  }
  return 255;
}

SampleRecord to_record(const Sample& sample) noexcept {
  SampleRecord record{};
  record.time = to_seconds(sample.time);
  record.distance_m = not_a_number;
  record.intensity = not_a_number;
  record.address = static_cast<std::int16_t>(sample.address);
  // One lookup of the family for the record (a bulk read converts millions of samples).
  const FamilyDescriptor* family = family_of(sample);
  record.kind = kind_number(family, sample);
  // The sample's reading (core/family.hpp) in metres, when it is a length at all.
  if (const auto reading = family != nullptr && family->reading != nullptr ? family->reading(sample) : std::nullopt) {
    if (const auto scale = metres_per(reading->channel->unit)) record.distance_m = reading->value * *scale;
  }
  // The columns only some families fill, by the sample's own family.
  if (const PythonFamily* python = find_python_family(sample.device); python != nullptr && python->fill_record)
    python->fill_record(sample, record);
  if (!std::isnan(record.distance_m)) record.flags |= flag::valid;
  if (sample.suspect) record.flags |= flag::suspect;
  return record;
}

py::array records_to_array(const std::vector<SampleRecord>& records) {
  py::array_t<SampleRecord> array(static_cast<py::ssize_t>(records.size()));
  SampleRecord* target = array.mutable_data();
  without_gil([&] {
    if (!records.empty()) std::memcpy(target, records.data(), records.size() * sizeof(SampleRecord));
    return 0;
  });
  return array;
}

py::object to_python(StreamItem item) {
  if (auto* sample = std::get_if<Sample>(&item)) return py::cast(std::move(*sample));
  return py::cast(std::get<StreamEvent>(std::move(item)));
}

void init_samples(py::module_& module) {
  PYBIND11_NUMPY_DTYPE(SampleRecord, time, distance_m, intensity, pulses, code, error, address, kind, flags, targets);
  module.attr("sample_dtype") = py::dtype::of<SampleRecord>();
  module.attr("FLAG_VALID") = flag::valid;
  module.attr("FLAG_NO_SIGNAL") = flag::no_signal;
  module.attr("FLAG_NO_RESULT_YET") = flag::no_result_yet;
  module.attr("FLAG_DERIVATIVE") = flag::derivative;
  module.attr("FLAG_PRESENCE") = flag::presence;
  module.attr("FLAG_PULSES_OVERFLOW") = flag::pulses_overflow;
  module.attr("FLAG_DEVICE_ERROR") = flag::device_error;
  module.attr("FLAG_SUSPECT") = flag::suspect;
  // The families' kinds one after another, in registration order: an array's `kind` numbers them.
  py::list kinds;
  for (const FamilyDescriptor* family : families()) {
    for (const KindDescriptor& kind : family->kinds) kinds.append(py::str(std::string(kind.name)));
  }
  module.attr("sample_kinds") = kinds;  // the `kind` column's values, by number

  py::class_<Sample> sample_class(module, "Sample",
                                  "One measurement as the host received it; the fields of docs/cli.md's JSON. "
                                  "A field of another family than the sample's reads None.");
  sample_class
      .def_property_readonly(
          "time", [](const Sample& s) { return to_seconds(s.time); },
          "host receive time, seconds since the Unix epoch (UTC)")
      .def_readonly("device", &Sample::device, "its family's name, one of rangekit.families()")
      .def_property_readonly(
          "source", [](const Sample& s) { return s.source.str(); }, "port path it came from")
      .def_readonly("address", &Sample::address, "bus address, -1 when the protocol has none")
      .def_property_readonly(
          "kind", [](const Sample& s) { return std::string(kind_name_of(s)); },
          "the kind's name, one of rangekit.sample_kinds")
      .def_property_readonly(
          "reading",
          [](const Sample& s) {
            const auto reading = reading_of(s);
            return reading ? py::cast(reading->value) : py::none();
          },
          "the one number the sample reports, as the dashboard, MQTT and captures do, or None (a gap)")
      .def_property_readonly(
          "reading_channel",
          [](const Sample& s) {
            const auto reading = reading_of(s);
            return reading ? py::cast(std::string(reading->channel->key)) : py::none();
          },
          "the channel the reading is of ('distance_m', 'targets', 'derivative_mm', ...), or None")
      .def_property_readonly(
          "reading_unit",
          [](const Sample& s) {
            const auto reading = reading_of(s);
            return reading ? py::cast(std::string(unit_symbol(reading->channel->unit))) : py::none();
          },
          "the reading's unit ('m', 'mm', '' for presence), or None")
      .def_readonly("suspect", &Sample::suspect,
                    "marked by the quality checks: a value no real target gives at this rate (docs/reliability.md)")
      .def_property_readonly(
          "suspect_reason", [](const Sample& s) { return s.suspect ? py::cast(s.suspect_reason) : py::none(); },
          "which check marked it and why, or None")
      .def_property_readonly("is_event", [](const Sample&) { return false; })
      .def("__repr__", [](const Sample& s) {
        std::string text = "<rangekit.Sample " + std::string(kind_name_of(s));
        if (const PythonFamily* family = find_python_family(s.device); family != nullptr && family->describe)
          text += family->describe(s);
        if (s.suspect) text += " suspect";
        return text + ">";
      });
  // Each family's own fields, from its folder (python/src/<family>/).
  for (const PythonFamily* family : python_families())
    if (family->sample_properties) family->sample_properties(sample_class);

  py::class_<StreamEvent>(module, "Event",
                          "A link event in a stream: connected, disconnected, reconnected, bad_frame, lost_records, "
                          "device_error or polling")
      .def_property_readonly(
          "time", [](const StreamEvent& e) { return to_seconds(e.time); }, "seconds since the Unix epoch (UTC)")
      .def_property_readonly(
          "kind", [](const StreamEvent& e) { return std::string(stream_event_kind_name(e.kind)); }, "the event's name")
      .def_readonly("message", &StreamEvent::message)
      .def_readonly("count", &StreamEvent::count, "records lost, for lost_records")
      .def_property_readonly("is_event", [](const StreamEvent&) { return true; })
      .def("__repr__", [](const StreamEvent& e) {
        return "<rangekit.Event " + std::string(stream_event_kind_name(e.kind)) +
               (e.message.empty() ? "" : ": " + e.message) + ">";
      });
}

}  // namespace rangekit::python
