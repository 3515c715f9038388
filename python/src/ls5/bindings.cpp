// rangekit.ls5: the LS5 host driver and codec (include/rangekit/ls5), settings by the
// table 9.2 names of `rangekit ls5 get/set` (ls5::HostSetting, through Driver::get/set).
#include <limits>
#include <memory>
#include <mutex>
#include <string>

#include "common.hpp"
#include "ls5/parts.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/ls5/driver.hpp"
#include "rangekit/ls5/host_settings.hpp"
#include "rangekit/ls5/udp_packet.hpp"

namespace rangekit::ls5::python {

using namespace rangekit::python;  // the module's shared helpers: py, unwrap, check, Stream, ...

namespace {

constexpr std::string_view family = "ls5";
// The stream reader lets records collect in the port this long between reads (the C++
// default is 2 ms): a Python consumer takes them at most every few milliseconds anyway, and
// 500 wake-ups a second were most of a 1 kHz stream's CPU (docs/python.md, Benchmark).
// 10 ms is 920 bytes at 921600 baud, far below the port buffer.
constexpr std::chrono::microseconds python_read_gather{10000};

py::object typed_value(const ls5::HostSetting* setting, const std::string& text) {
  if (setting == nullptr || !ls5::setting_is_numeric(*setting)) return py::str(text);
  try {
    if (text.find_first_of(".eE") == std::string::npos) return py::int_(py::str(text));
    return py::float_(py::str(text));
  } catch (const py::error_already_set&) {
    return py::str(text);
  }
}

// The driver is used by one call at a time: Python threads take turns here (without the GIL).
class Ls5Device {
 public:
  Ls5Device(std::unique_ptr<ls5::Driver> driver, std::string port)
      : driver_(std::move(driver)), port_(std::move(port)) {}
  ~Ls5Device() { close(); }
  void close() {
    py::gil_scoped_release release;
    std::lock_guard lock(mutex_);
    driver_.reset();  // a running stream is stopped first (SB); the stream object then reads as finished
  }
  template <class Call>
  auto call(Call&& work) {
    if (!driver_) throw py::value_error("this LS5 driver (" + port_ + ") is closed");
    py::gil_scoped_release release;
    std::lock_guard lock(mutex_);
    return work(*driver_);
  }
  [[nodiscard]] const std::string& port() const { return port_; }

 private:
  std::mutex mutex_;
  std::unique_ptr<ls5::Driver> driver_;
  std::string port_;
};

py::dict info_dict(const ls5::SensorInfo& info) {
  py::dict result;
  result["address"] = info.address;
  result["version"] = std::string(info.identification.version_text.view());
  result["lower_boundary_mm"] = info.identification.lower_boundary_mm;
  result["range_mm"] = info.identification.range_mm;
  result["serial_number"] = info.identification.serial_number;
  result["ethernet"] = info.ethernet;
  return result;
}

}  // namespace

void bind(py::module_& parent) {
  py::module_ module = parent.def_submodule("ls5", "Prizma LS5: driver and codec");

  py::class_<Ls5Device>(module, "Driver", "An LS5 on a serial port (rangekit::ls5::Driver).")
      .def("close", &Ls5Device::close, "Closes the port; a running stream is stopped first (SB).")
      .def_property_readonly("port", &Ls5Device::port)
      .def(
          "get",
          [](Ls5Device& device, const std::string& name) {
            auto reading = unwrap(device.call([&](ls5::Driver& driver) { return driver.get(name); }), family);
            return typed_value(reading.setting, reading.text);
          },
          py::arg("name"), "One table 9.2 setting by name (thinning, period-ms, ...), as int, float or str")
      .def(
          "set_many",
          [](Ls5Device& device, const std::vector<std::pair<std::string, std::string>>& pairs) {
            // Every value checked (range, firmware) before the first byte of the first is sent.
            // Names and table 9.2 ranges first, before even the ID the sensor's own checks need.
            for (const auto& [name, text] : pairs) {
              const ls5::HostSetting* setting = ls5::find_host_setting(name);
              if (setting == nullptr)
                check(make_error(Errc::unknown_parameter, "no LS5 setting named '" + name + "'"), family);
              else
                check(ls5::check_setting_offline(*setting, text), family);
            }
            check(device.call([&](ls5::Driver& driver) -> Status {
              auto context = driver.context();
              if (!context) return context.error();
              for (const auto& [name, text] : pairs) {
                const ls5::HostSetting* setting = ls5::find_host_setting(name);
                if (setting == nullptr)
                  return make_error(Errc::unknown_parameter, "no LS5 setting named '" + name + "'");
                auto writes = ls5::encode_setting(*setting, text, *context);
                if (!writes) return writes.error();
              }
              for (const auto& [name, text] : pairs) {
                Status written = driver.set(name, text);
                if (!written) return written;
              }
              return ok_status();
            }),
                  family);
          },
          py::arg("pairs"), "[(name, text), ...]: every value checked before anything is sent, then written in order")
      .def(
          "get_all",
          [](Ls5Device& device) {
            auto values = unwrap(device.call([](ls5::Driver& driver) { return driver.read_all_settings(); }), family);
            py::dict result;
            for (const auto& value : values)
              result[py::str(value.name)] = typed_value(ls5::find_host_setting(value.name), value.text);
            return result;
          },
          "Every setting this sensor has, in table order, as `rangekit ls5 get` lists them")
      .def(
          "info",
          [](Ls5Device& device) {
            return info_dict(unwrap(device.call([](ls5::Driver& driver) { return driver.info(); }), family));
          },
          "ID (and R70 on LS5.12+): version, lower_boundary_mm, range_mm, serial_number, ethernet")
      .def(
          "measure",
          [](Ls5Device& device) {
            return unwrap(device.call([&](ls5::Driver& driver) -> Result<Sample> {
              auto context = driver.context();
              if (!context) return context.error();
              auto last = driver.read_last();
              if (!last) return last.error();
              return ls5::make_ls5_sample(last->code, context->range_mm, driver.transport_name(), driver.address(),
                                          last->derivative);
            }),
                          family);
          },
          "The last result (LR) as a Sample")
      .def(
          "start_measuring",
          [](Ls5Device& device) {
            check(device.call([](ls5::Driver& driver) { return driver.start_measuring(); }), family);
          },
          "ON: the sensor measures")
      .def(
          "stop_measuring",
          [](Ls5Device& device) {
            check(device.call([](ls5::Driver& driver) { return driver.stop_measuring(); }), family);
          },
          "OF: the sensor stops measuring")
      .def(
          "save",
          [](Ls5Device& device) {
            check(device.call([](ls5::Driver& driver) { return driver.store_to_flash(); }), family);
          },
          "FL: the parameters into flash")
      .def(
          "restore_defaults",
          [](Ls5Device& device) {
            check(device.call([](ls5::Driver& driver) { return driver.restore_defaults(); }), family);
          },
          "DF: factory parameters, in RAM until save() (L27)")
      .def(
          "stream",
          [](Ls5Device& device, std::optional<int> thinning, double reconnect_interval, double silence_timeout,
             bool check_quality, std::optional<double> max_speed, bool drop_suspect, std::size_t queue_capacity) {
            const StreamQuality quality = stream_quality(check_quality, max_speed, drop_suspect);
            ls5::Driver::StreamOptions options;
            if (thinning) {
              if (*thinning < 0 || *thinning > 255) throw py::value_error("thinning must be 0-255 (§8.4)");
              options.thinning = static_cast<std::uint8_t>(*thinning);
            }
            options.reconnect_interval = std::chrono::milliseconds(static_cast<long>(reconnect_interval * 1000.0));
            options.silence_timeout = std::chrono::milliseconds(static_cast<long>(silence_timeout * 1000.0));
            options.read_gather = python_read_gather;
            if (queue_capacity < 1) throw py::value_error("queue_capacity must be 1 or more records");
            options.queue_capacity = queue_capacity;
            auto stream =
                unwrap(device.call([&](ls5::Driver& driver) { return driver.start_stream(options); }), family);
            return std::make_unique<Stream>(SampleSourcePtr(std::move(stream)), quality);
          },
          py::arg("thinning") = py::none(), py::arg("reconnect_interval") = 0.5, py::arg("silence_timeout") = 3.0,
          py::kw_only(), py::arg("check_quality") = true, py::arg("max_speed") = py::none(),
          py::arg("drop_suspect") = false, py::arg("queue_capacity") = ls5::Driver::StreamOptions{}.queue_capacity,
          py::keep_alive<0, 1>(),
          "Starts the record stream (ST, optionally writing thinning n first, §8.4) and returns the Stream. "
          "Each sample is checked as `rangekit ls5 stream` does: one further from the running median than "
          "max_speed (m/s; default the range a second) allows is marked suspect, or left out with drop_suspect. "
          "queue_capacity records wait for the reader at most; beyond it the oldest are dropped and a "
          "lost_records event says how many.");

  module.def(
      "open",
      [](const std::string& port, std::uint32_t baud, int address, double timeout) {
        if (address < 0 || address > 255) throw py::value_error("address must be 0-255 (§8.1)");
        if (!(timeout > 0)) throw py::value_error("timeout must be more than 0 seconds");
        ls5::DriverOptions options;
        options.address = static_cast<std::uint8_t>(address);
        options.timeout = std::chrono::milliseconds(static_cast<long>(timeout * 1000.0));
        const SerialSettings settings{baud, Parity::none, 1};
        auto link = unwrap(without_gil([&] { return open_serial_link(port, settings); }), family);
        auto driver = std::make_unique<ls5::Driver>(std::move(link), options,
                                                    [port, settings] { return open_serial_link(port, settings); });
        return std::make_unique<Ls5Device>(std::move(driver), port);
      },
      py::arg("port"), py::arg("baud") = 115200, py::arg("address") = 1, py::arg("timeout") = 0.5);

  module.def(
      "parse_udp",
      [](const py::bytes& packet) {
        const std::string bytes = packet;
        auto view = std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
        auto decoded = unwrap(ls5::decode_udp_packet(view), family);
        py::list names;
        for (const char* name : {"code", "state", "distance_mm"}) names.append(name);
        py::list formats;
        for (const char* format : {"<u2", "u1", "<f8"}) formats.append(format);
        py::dict spec;
        spec["names"] = names;
        spec["formats"] = formats;
        py::dtype dtype = py::dtype::from_args(spec);
        py::array records(dtype, py::ssize_t(ls5::udp_record_count));
        py::array_t<std::uint16_t> codes(static_cast<py::ssize_t>(ls5::udp_record_count));
        py::array_t<std::uint8_t> states(static_cast<py::ssize_t>(ls5::udp_record_count));
        py::array_t<double> distances(static_cast<py::ssize_t>(ls5::udp_record_count));
        for (std::size_t i = 0; i < ls5::udp_record_count; ++i) {
          const auto& record = decoded.records[i];
          codes.mutable_at(static_cast<py::ssize_t>(i)) = record.code;
          states.mutable_at(static_cast<py::ssize_t>(i)) = record.state;
          auto mm = ls5::udp_distance_mm(record, decoded.range_mm);  // formula 10.1
          distances.mutable_at(static_cast<py::ssize_t>(i)) = mm ? *mm : std::numeric_limits<double>::quiet_NaN();
        }
        records[py::str("code")] = codes;
        records[py::str("state")] = states;
        records[py::str("distance_mm")] = distances;
        py::dict result;
        result["records"] = records;
        result["serial_number"] = decoded.serial_number;
        result["lower_boundary_mm"] = decoded.lower_boundary_mm;
        result["range_mm"] = decoded.range_mm;
        result["counter"] = decoded.counter;
        return result;
      },
      py::arg("packet"),
      "One 512-byte Ethernet datagram (§10.1): records (code, state, distance_mm by formula 10.1, NaN when "
      "not a measured in-range distance), serial_number, lower_boundary_mm, range_mm, counter");

  module.def(
      "setting_units",
      [] {
        py::dict units;
        for (const auto& setting : ls5::host_setting_table())
          units[py::str(std::string(setting.name))] = std::string(setting.unit);
        return units;
      },
      "Every table 9.2 setting name and its unit ('ms', 'mm', 'code', '' ...)");
  module.def(
      "setting_ranges",
      [] {
        ls5::SettingContext newest;  // the values of the newest firmware; *-mm ones scale with the sensor's range
        newest.model.firmware = ls5::FirmwareVersion{0xFFFF, 0xFFFF};
        newest.model.ethernet = true;
        py::dict ranges;
        for (const auto& setting : ls5::host_setting_table())
          ranges[py::str(std::string(setting.name))] = ls5::describe_setting_values(setting, newest);
        return ranges;
      },
      "Every table 9.2 setting name and the values set accepts (newest firmware; -mm ones need the range)");
}

}  // namespace rangekit::ls5::python
