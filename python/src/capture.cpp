// rangekit.capture: a SQLite capture (docs/capture.md) read into NumPy in one pass,
// through the replay of rangekit::record at full speed, without the GIL.
#include <string>

#include "common.hpp"
#include "rangekit/record/replay.hpp"

namespace rangekit::python {

void init_capture(py::module_& parent) {
  py::module_ module = parent.def_submodule("capture", "SQLite captures");
  module.def(
      "read",
      [](const std::string& path, const std::string& device) {
        if (!device.empty() && device != "uls" && device != "ls5")
          throw py::value_error("device '" + device + "' must be 'uls', 'ls5' or '' (both)");
        record::ReplayOptions options;
        options.speed = 0;  // as fast as it reads
        options.device = device;
        auto source = unwrap(without_gil([&] { return record::open_replay(path, options); }));
        std::vector<SampleRecord> records;
        std::vector<StreamEvent> events;
        without_gil([&] {
          while (true) {
            auto item = source->next(std::chrono::milliseconds(0));
            if (!item) {
              if (source->finished()) break;
              continue;
            }
            if (const auto* sample = std::get_if<Sample>(&*item)) {
              records.push_back(to_record(*sample));
            } else {
              events.push_back(std::get<StreamEvent>(std::move(*item)));
            }
          }
          return 0;
        });
        py::list event_objects;
        for (StreamEvent& event : events) event_objects.append(py::cast(std::move(event)));
        return py::make_tuple(records_to_array(records), event_objects);
      },
      py::arg("path"), py::arg("device") = "",
      "(samples as a NumPy structured array of rangekit.sample_dtype, [Event, ...]) of a capture file; "
      "device 'uls' or 'ls5' keeps one family's samples");
}

}  // namespace rangekit::python
