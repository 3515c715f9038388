// Samples and events as Python objects, the NumPy record, and errors as exceptions.
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "common.hpp"
#include "rangekit/core/family.hpp"
#include "rangekit/uls/errors.hpp"

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

template <class T>
py::object optional_object(const std::optional<T>& value) {
  return value ? py::cast(*value) : py::none();
}

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

SampleRecord to_record(const Sample& sample) noexcept {
  SampleRecord record{};
  record.time = to_seconds(sample.time);
  record.distance_m = not_a_number;
  record.intensity = not_a_number;
  record.address = static_cast<std::int16_t>(sample.address);
  record.kind = static_cast<std::uint8_t>(sample.kind);
  std::uint8_t flags = 0;
  // The sample's reading (core/family.hpp) in metres, when it is a length at all.
  if (const auto reading = reading_of(sample)) {
    if (const auto scale = metres_per(reading->channel->unit)) record.distance_m = reading->value * *scale;
  }
  if (!std::isnan(record.distance_m)) flags |= flag::valid;
  if (sample.pulse_width) {
    record.intensity = static_cast<double>(*sample.pulse_width) / 1000.0;  // ps on the wire (U8), ns here
  } else if (!sample.targets.empty()) {
    record.intensity = static_cast<double>(sample.targets.front().strength);
  }
  record.targets = static_cast<std::uint8_t>(sample.targets.size());
  record.pulses = sample.pulses_between_events.value_or(0);
  record.code = sample.code.value_or(0);
  if (sample.device_error) {
    record.error = static_cast<std::int16_t>(*sample.device_error);
    flags |= flag::device_error;
    if (*sample.device_error == uls::error_number::target_not_found) flags |= flag::no_signal;
    if (*sample.device_error == uls::error_number::average_not_filled) flags |= flag::no_result_yet;
  }
  if (sample.signal == SignalState::lost) flags |= flag::no_signal;
  if (sample.signal == SignalState::none_yet) flags |= flag::no_result_yet;
  if (sample.kind == SampleKind::ls5_derivative) flags |= flag::derivative;
  if (sample.presence.value_or(false)) flags |= flag::presence;
  if (sample.pulses_overflow) flags |= flag::pulses_overflow;
  if (sample.suspect) flags |= flag::suspect;
  record.flags = flags;
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
  py::list kinds;
  for (auto kind : {SampleKind::uls_averaging, SampleKind::uls_binning, SampleKind::uls_look_down,
                    SampleKind::uls_error, SampleKind::ls5_result, SampleKind::ls5_derivative})
    kinds.append(sample_kind_name(kind));
  module.attr("sample_kinds") = kinds;  // the `kind` column's values, by number

  py::class_<Sample>(module, "Sample",
                     "One measurement as the host received it (ULS or LS5); the fields of docs/cli.md's JSON.")
      .def_property_readonly(
          "time", [](const Sample& s) { return to_seconds(s.time); },
          "host receive time, seconds since the Unix epoch (UTC)")
      .def_readonly("device", &Sample::device, "'uls' or 'ls5'")
      .def_property_readonly(
          "source", [](const Sample& s) { return s.source.str(); }, "port path it came from")
      .def_readonly("address", &Sample::address, "bus address, -1 when the protocol has none")
      .def_property_readonly(
          "kind", [](const Sample& s) { return std::string(sample_kind_name(s.kind)); },
          "averaging, binning, look_down, error (ULS); result, derivative (LS5)")
      .def_property_readonly(
          "distance_m", [](const Sample& s) { return optional_object(s.distance_m); },
          "ULS averaging distance in metres, or None")
      .def_property_readonly(
          "pulse_width", [](const Sample& s) { return optional_object(s.pulse_width); },
          "ULS pulse width in picoseconds as on the wire, or None")
      .def_property_readonly(
          "pulse_width_ns",
          [](const Sample& s) {
            return s.pulse_width ? py::cast(static_cast<double>(*s.pulse_width) / 1000.0) : py::none();
          },
          "ULS pulse width in nanoseconds, or None")
      .def_property_readonly(
          "targets",
          [](const Sample& s) {
            py::list targets;
            for (const TargetHit& hit : s.targets) targets.append(py::make_tuple(hit.distance_m, hit.strength));
            return targets;
          },
          "ULS binning: [(distance_m, strength), ...], strength in hits of the target's bin")
      .def_property_readonly(
          "presence", [](const Sample& s) { return optional_object(s.presence); },
          "ULS look down: a target present, or None")
      .def_property_readonly(
          "pulses_between_events", [](const Sample& s) { return optional_object(s.pulses_between_events); },
          "ULS look down with TB: pulses between the edges (1-65535), or None")
      .def_readonly("pulses_overflow", &Sample::pulses_overflow, "ULS look down: more than 65535 pulses (U88)")
      .def_property_readonly(
          "device_error", [](const Sample& s) { return optional_object(s.device_error); },
          "ULS $ER,n error number (§10), or None")
      .def_property_readonly(
          "error_text",
          [](const Sample& s) { return s.device_error ? py::cast(error_text_of(s, *s.device_error)) : py::none(); },
          "the §10 text of device_error, or None")
      .def_property_readonly(
          "code", [](const Sample& s) { return optional_object(s.code); }, "LS5 result code 0-65535 (§9.3), or None")
      .def_property_readonly(
          "distance_mm", [](const Sample& s) { return optional_object(s.distance_mm); },
          "LS5 distance in millimetres (formula 8.1), None for 65534/65535")
      .def_property_readonly(
          "derivative_mm", [](const Sample& s) { return optional_object(s.derivative_mm); },
          "LS5 distance derivative in millimetres (formula 8.2), or None")
      .def_property_readonly(
          "signal",
          [](const Sample& s) { return s.signal ? py::cast(std::string(signal_state_name(*s.signal))) : py::none(); },
          "LS5: 'ok', 'none_yet' (65534) or 'lost' (65535), or None")
      .def_property_readonly(
          "resolution_mm", [](const Sample& s) { return optional_object(s.resolution_mm); },
          "LS5: the sensor's discreteness in millimetres (table 3.1), or None")
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
        std::string text = "<rangekit.Sample " + std::string(sample_kind_name(s.kind));
        if (s.distance_m) text += " distance_m=" + std::to_string(*s.distance_m);
        if (s.distance_mm) text += " distance_mm=" + std::to_string(*s.distance_mm);
        if (s.code) text += " code=" + std::to_string(*s.code);
        if (s.device_error) text += " device_error=" + std::to_string(*s.device_error);
        if (s.suspect) text += " suspect";
        return text + ">";
      });

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
