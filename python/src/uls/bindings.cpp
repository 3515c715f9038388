// rangekit.uls: the ULS host driver and codec (include/rangekit/uls), settings by the
// names of `rangekit uls get/set` (uls::named, the table the CLI and the service use).
#include <memory>
#include <string>

#include "common.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/uls/bus.hpp"
#include "rangekit/uls/describe.hpp"
#include "rangekit/uls/driver.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/measurement.hpp"
#include "rangekit/uls/named_settings.hpp"
#include "uls/parts.hpp"

namespace rangekit::uls::python {

using namespace rangekit::python;  // the module's shared helpers: py, unwrap, check, Stream, ...

namespace {

Result<TransportPtr> open_line(const std::string& path, std::uint32_t baud) {
  return open_serial_link(path, SerialSettings{baud, Parity::none, 1});  // 8N1, §9
}

// A get's text as a Python value: numbers as int or float, lists of numbers as lists.
py::object typed_value(const std::string& text, bool number) {
  if (!number) return py::str(text);
  if (text.find(',') != std::string::npos) {
    py::list values;
    std::size_t start = 0;
    while (start <= text.size()) {
      const std::size_t comma = std::min(text.find(',', start), text.size());
      values.append(typed_value(text.substr(start, comma - start), true));
      start = comma + 1;
    }
    return values;
  }
  try {
    if (text.find_first_of(".eE") == std::string::npos) return py::int_(py::str(text));
    return py::float_(py::str(text));
  } catch (const py::error_already_set&) {
    return py::str(text);
  }
}

uls::Mode parse_mode(const std::string& text) {
  if (text == "averaging") return uls::Mode::averaging;
  if (text == "binning") return uls::Mode::binning;
  if (text == "look-down" || text == "look_down") return uls::Mode::look_down;
  throw py::value_error("mode '" + text + "' must be averaging, binning or look-down (§8 MM)");
}
uls::DisplayMode parse_display(const std::string& text) {
  if (text == "range") return uls::DisplayMode::range;
  if (text == "range-and-intensity" || text == "range_and_intensity") return uls::DisplayMode::range_and_intensity;
  if (text == "intensity") return uls::DisplayMode::intensity;
  throw py::value_error("display '" + text + "' must be range, range-and-intensity or intensity (§8 DM)");
}
uls::Units parse_units(const std::string& text) {
  if (text == "metres") return uls::Units::metres;
  if (text == "feet") return uls::Units::feet;
  throw py::value_error("units '" + text + "' must be metres or feet (§8 MU)");
}
uls::StreamMode parse_stream_mode(const std::string& text) {
  if (text == "automatic") return uls::StreamMode::automatic;
  if (text == "continuous") return uls::StreamMode::continuous;
  if (text == "polled") return uls::StreamMode::polled;
  throw py::value_error("stream mode '" + text + "' must be automatic, continuous or polled");
}

py::dict status_dict(const uls::StatusInfo& status) {
  py::dict result;
  result["value"] = status.value;
  result["active"] = status.active;
  result["laser_firing"] = status.laser_firing;
  result["measuring"] = status.measuring();
  result["averaging_calc"] = status.averaging_calc;
  result["binning_calc"] = status.binning_calc;
  const char* mode = nullptr;
  if (status.mode == uls::Mode::averaging) mode = "averaging";
  if (status.mode == uls::Mode::binning) mode = "binning";
  if (status.mode == uls::Mode::look_down) mode = "look-down";
  result["mode"] = mode != nullptr ? py::object(py::str(mode)) : py::none();
  return result;
}

class UlsDevice {
 public:
  UlsDevice(std::unique_ptr<uls::Driver> driver, std::string port)
      : driver_(std::move(driver)), port_(std::move(port)) {}
  ~UlsDevice() { close(); }
  void close() {
    py::gil_scoped_release release;
    driver_.reset();  // ends a running stream as the driver's destructor says (U86)
  }
  uls::Driver& driver() {
    if (!driver_) throw py::value_error("this ULS driver (" + port_ + ") is closed");
    return *driver_;
  }
  [[nodiscard]] const std::string& port() const { return port_; }

 private:
  std::unique_ptr<uls::Driver> driver_;
  std::string port_;
};

constexpr std::string_view family = "uls";

py::object read_one(UlsDevice& device, const std::string& name) {
  auto target = unwrap(uls::named::find_setting(name, uls::named::Purpose::get), family);
  uls::Driver& driver = device.driver();
  auto values = without_gil([&]() -> Result<std::vector<uls::named::Value>> {
    auto units = driver.units();
    if (!units) return units.error();
    return uls::named::read_setting(driver, target, *units);
  });
  auto lines = unwrap(std::move(values), family);
  if (lines.size() == 1) return typed_value(lines[0].reading.text, lines[0].reading.number);
  py::dict result;  // BR: one value per port
  for (const auto& line : lines) result[py::str(line.key)] = typed_value(line.reading.text, line.reading.number);
  return result;
}

void write_many(UlsDevice& device, const std::vector<std::pair<std::string, std::string>>& pairs) {
  // Every value checked before the first is sent (uls::named::plan), as `rangekit uls set`.
  auto assignments = unwrap(uls::named::plan(pairs), family);
  uls::Driver& driver = device.driver();
  check(without_gil([&] { return uls::named::apply(driver, assignments); }), family);
}

}  // namespace

void bind(py::module_& parent) {
  py::module_ module = parent.def_submodule("uls", "LTI ULS: driver and codec");

  py::class_<UlsDevice>(module, "Driver", "A ULS unit on a serial port (rangekit::uls::Driver).")
      .def("close", &UlsDevice::close, "Closes the port; a running stream ends first (U86).")
      .def_property_readonly("port", &UlsDevice::port)
      .def("get", &read_one, py::arg("name"),
           "One setting by the name `rangekit uls get` prints (prf-hz, mode, short-gate-m, ...) or its mnemonic, "
           "as int, float, list or str")
      .def("set_many", &write_many, py::arg("pairs"),
           "[(name, text), ...]: every value checked before anything is sent, then written in order")
      .def(
          "get_all",
          [](UlsDevice& device) {
            uls::Driver& driver = device.driver();
            auto lines = unwrap(without_gil([&] { return uls::named::read_all(driver); }), family);
            py::dict result;
            for (const auto& line : lines)
              result[py::str(line.key)] = typed_value(line.reading.text, line.reading.number);
            return result;
          },
          "Every readable setting, in table order, as `rangekit uls get` lists them")
      .def(
          "info",
          [](UlsDevice& device) {
            uls::Driver& driver = device.driver();
            auto info = unwrap(without_gil([&] { return driver.info(); }), family);
            py::dict result;
            result["version"] = info.version;
            result["status"] = status_dict(info.status);
            result["address"] =
                info.address ? py::object(py::str(uls::address_text(*info.address))) : py::object(py::none());
            return result;
          },
          "ID and US: {'version': ..., 'status': {...}, 'address': ...}")
      .def(
          "status",
          [](UlsDevice& device) {
            uls::Driver& driver = device.driver();
            return status_dict(unwrap(without_gil([&] { return driver.status(); }), family));
          },
          "US decoded into its bits (§8 Get Unit Status)")
      .def(
          "measure",
          [](UlsDevice& device) {
            uls::Driver& driver = device.driver();
            return unwrap(without_gil([&] { return driver.measure(); }), family);
          },
          "One reading with BM (a whole target array in binning); starts an idle unit (§2 Autostart)")
      .def(
          "start_measuring",
          [](UlsDevice& device) {
            uls::Driver& driver = device.driver();
            check(without_gil([&] { return driver.start_measuring(); }), family);
          },
          "GO")
      .def(
          "stop_measuring",
          [](UlsDevice& device) {
            uls::Driver& driver = device.driver();
            check(without_gil([&] { return driver.stop_measuring(); }), family);
          },
          "ST (ends the stream's reader first when streaming)")
      .def(
          "save",
          [](UlsDevice& device) {
            uls::Driver& driver = device.driver();
            check(without_gil([&] { return driver.save(); }), family);
          },
          "SU: the user settings into non-volatile memory")
      .def(
          "stream",
          [](UlsDevice& device, const std::string& mode, bool check_quality, std::optional<double> max_speed,
             bool drop_suspect) {
            const StreamQuality quality = stream_quality(check_quality, max_speed, drop_suspect);
            uls::Driver& driver = device.driver();
            const uls::StreamMode stream_mode = parse_stream_mode(mode);
            auto stream = unwrap(without_gil([&] { return driver.start_stream(stream_mode); }), family);
            return std::make_unique<Stream>(SampleSourcePtr(std::move(stream)), quality);
          },
          py::arg("mode") = "automatic", py::kw_only(), py::arg("check_quality") = true,
          py::arg("max_speed") = py::none(), py::arg("drop_suspect") = false, py::keep_alive<0, 1>(),
          "Starts measuring (GO unless already measuring) and returns the Stream; mode automatic, continuous "
          "or polled. Each sample is checked as `rangekit uls stream` does: a distance further from the running "
          "median than max_speed (m/s; default 25) allows, or a pulse width off by more than 2x, is marked "
          "suspect, or left out with drop_suspect.");

  module.def(
      "open",
      [](const std::string& port, std::uint32_t baud, std::optional<std::string> address, double timeout) {
        uls::DriverOptions options;
        if (address) {
          auto byte = uls::parse_unit_address(*address);
          if (!byte)
            throw py::value_error("address '" + *address + "' is not a unit address 0x30..0xEF (§8 RS485 Protocol)");
          options.address = *byte;
        }
        if (!(timeout > 0)) throw py::value_error("timeout must be more than 0 seconds");
        options.timeout = std::chrono::milliseconds(static_cast<long>(timeout * 1000.0));
        options.source = port;
        auto link = unwrap(without_gil([&] { return open_line(port, baud); }), family);
        auto driver =
            std::make_unique<uls::Driver>(std::move(link), options, [port, baud] { return open_line(port, baud); });
        return std::make_unique<UlsDevice>(std::move(driver), port);
      },
      py::arg("port"), py::arg("baud") = 115200, py::arg("address") = py::none(), py::arg("timeout") = 1.0);

  module.def(
      "decode_line",
      [](const py::bytes& line, const std::string& mode, const std::string& display, const std::string& units,
         bool time_between_events) {
        std::string bytes = line;
        // One line as the unit sends it: its CR (§9) ends it; the codec takes the frame without it.
        if (!bytes.empty() && bytes.back() == '\r') bytes.pop_back();
        uls::MeasurementContext context;
        context.mode = parse_mode(mode);
        context.display = parse_display(display);
        context.units = parse_units(units);
        context.time_between_events = time_between_events;
        auto view = std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
        auto measurement = unwrap(uls::decode_measurement(view, context), family);
        const int address = measurement.source.addressed ? measurement.source.byte : -1;
        return uls::sample_from_reading(measurement.reading, address, "");
      },
      py::arg("line"), py::kw_only(), py::arg("mode") = "averaging", py::arg("display") = "range",
      py::arg("units") = "metres", py::arg("time_between_events") = false);

  module.def("error_text", &uls::error_text, py::arg("number"), "The §10 text of a ULS error number");
  module.def(
      "writable_names", [] { return uls::named::writable_names(); }, "The names set accepts, comma separated");
  module.def(
      "readable_names",
      [] {
        std::vector<std::string> names;
        for (const auto& target : uls::named::readable_targets())
          names.push_back(uls::named::setting_key(*target.command));
        return names;
      },
      "The names get accepts, in table order");
  module.def(
      "setting_ranges",
      [] {
        py::dict ranges;
        for (const auto& target : uls::named::readable_targets())
          ranges[py::str(uls::named::setting_key(*target.command))] =
              target.command->has_set() ? uls::allowed_values(*target.command, uls::Units::metres) : "read only";
        return ranges;
      },
      "Every setting name and what set accepts for it (§8's ranges, distances in metres)");
}

}  // namespace rangekit::uls::python
