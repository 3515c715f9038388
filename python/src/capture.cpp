// rangekit.capture: a SQLite capture (docs/capture.md) read into NumPy in one pass,
// through rangekit::record's bulk reader (for_each_in_capture), without the GIL.
#include <cstring>
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
        // Records gather in fixed chunks (no reallocation copying what was read) and are
        // copied once into the array.
        constexpr std::size_t chunk_size = 1U << 16U;
        std::vector<std::vector<SampleRecord>> chunks;
        std::size_t total = 0;
        std::vector<StreamEvent> events;
        const Status read = without_gil([&] {
          return record::for_each_in_capture(
              path, device,
              [&](const Sample& sample) {
                if (chunks.empty() || chunks.back().size() == chunk_size) chunks.emplace_back().reserve(chunk_size);
                chunks.back().push_back(to_record(sample));
                ++total;
              },
              [&](StreamEvent&& event) { events.push_back(std::move(event)); });
        });
        check(read);
        py::array_t<SampleRecord> samples(static_cast<py::ssize_t>(total));
        SampleRecord* target = samples.mutable_data();
        without_gil([&] {
          for (const auto& chunk : chunks) {
            std::memcpy(target, chunk.data(), chunk.size() * sizeof(SampleRecord));
            target += chunk.size();
          }
          return 0;
        });
        py::list event_objects;
        for (StreamEvent& event : events) event_objects.append(py::cast(std::move(event)));
        return py::make_tuple(samples, event_objects);
      },
      py::arg("path"), py::arg("device") = "",
      "(samples as a NumPy structured array of rangekit.sample_dtype, [Event, ...]) of a capture file; "
      "device 'uls' or 'ls5' keeps one family's samples");
}

}  // namespace rangekit::python
