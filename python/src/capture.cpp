// rangekit.capture: a SQLite capture (docs/capture.md) read into NumPy in one pass,
// through rangekit::record's bulk reader (for_each_in_capture) straight into the array,
// without the GIL.
#include <cstring>
#include <string>
#include <vector>

#include "common.hpp"
#include "rangekit/core/family.hpp"
#include "rangekit/record/replay.hpp"

namespace rangekit::python {

namespace {

// "" is every family; any other name must be a registered one.
void check_family(const std::string& device) {
  if (device.empty() || find_family(device) != nullptr) return;
  std::string known;
  for (const FamilyDescriptor* family : families()) known += "'" + std::string(family->name) + "', ";
  throw py::value_error("device '" + device + "' must be " + known + "or '' (every family)");
}

}  // namespace

void init_capture(py::module_& parent) {
  py::module_ module = parent.def_submodule("capture", "SQLite captures");
  module.def(
      "samples",
      [](const std::string& path, const std::string& device) {
        check_family(device);
        std::vector<Sample> samples;
        check(without_gil([&] {
          return record::for_each_in_capture(
              path, device, [&](const Sample& sample) { samples.push_back(sample); }, [](StreamEvent&&) {});
        }));
        py::list objects;
        for (Sample& sample : samples) objects.append(py::cast(std::move(sample)));
        return objects;
      },
      py::arg("path"), py::arg("device") = "",
      "[Sample, ...] of a capture file, every field as a live stream gives it; device keeps one family's samples");
  module.def(
      "read",
      [](const std::string& path, const std::string& device) {
        check_family(device);
        // The array is allocated once, for the most samples the capture can hold, and filled
        // as the rows are read; the pages past the last sample are never touched, and the
        // array is shrunk in place at the end.
        const std::size_t bound = unwrap(record::capture_sample_bound(path));
        py::array_t<SampleRecord> samples(static_cast<py::ssize_t>(bound));
        SampleRecord* const target = samples.mutable_data();
        std::vector<SampleRecord> beyond_bound;  // a capture written while it is read
        std::size_t total = 0;
        std::vector<StreamEvent> events;
        const Status read = without_gil([&] {
          return record::for_each_in_capture(
              path, device,
              [&](const Sample& sample) {
                if (total < bound) {
                  target[total] = to_record(sample);
                } else {
                  beyond_bound.push_back(to_record(sample));
                }
                ++total;
              },
              [&](StreamEvent&& event) { events.push_back(std::move(event)); }, record::CaptureFields::array);
        });
        check(read);
        if (!beyond_bound.empty()) {
          py::array_t<SampleRecord> all(static_cast<py::ssize_t>(total));
          std::memcpy(all.mutable_data(), target, bound * sizeof(SampleRecord));
          std::memcpy(all.mutable_data() + bound, beyond_bound.data(), beyond_bound.size() * sizeof(SampleRecord));
          samples = std::move(all);
        } else if (total < bound) {
          samples.resize({static_cast<py::ssize_t>(total)});
        }
        py::list event_objects;
        for (StreamEvent& event : events) event_objects.append(py::cast(std::move(event)));
        return py::make_tuple(samples, event_objects);
      },
      py::arg("path"), py::arg("device") = "",
      "(samples as a NumPy structured array of rangekit.sample_dtype, [Event, ...]) of a capture file; "
      "device (a family's name) keeps that family's samples");
}

}  // namespace rangekit::python
