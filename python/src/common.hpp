// Shared by the parts of the `_rangekit` module: errors raised as the Python
// exceptions of rangekit.errors, calls made without the GIL, the sample record
// of the NumPy arrays, and the wait for the next stream item that stays
// responsive to Ctrl-C.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/core/sample_quality.hpp"

namespace rangekit::python {

namespace py = pybind11;

// Raises the rangekit.errors class for the error's code, carrying the code's name,
// the device's error number and the family's text for it (FamilyDescriptor::error_text).
[[noreturn]] void raise_error(const Error& error, std::string_view family = {});

template <class T>
T unwrap(Result<T> result, std::string_view family = {}) {
  if (!result) raise_error(result.error(), family);
  return std::move(result).value();
}
inline void check(const Status& status, std::string_view family = {}) {
  if (!status) raise_error(status.error(), family);
}

// Runs `call` with the GIL released (waiting for a device, filling an array).
template <class Call>
auto without_gil(Call&& call) {
  py::gil_scoped_release release;
  return call();
}

double to_seconds(std::chrono::system_clock::time_point time) noexcept;

// An optional field as its value, or None.
template <class T>
py::object optional_object(const std::optional<T>& value) {
  return value ? py::cast(*value) : py::none();
}

// Bits of SampleRecord::flags (rangekit.FLAG_* in Python). Beyond valid and suspect, a
// family's part (python_family.hpp) sets those its samples can carry; docs/python.md says which.
namespace flag {
inline constexpr std::uint8_t valid = 0x01;            // distance_m holds the sample's reading
inline constexpr std::uint8_t no_signal = 0x02;        // the sensor found no target
inline constexpr std::uint8_t no_result_yet = 0x04;    // the sensor has no result yet (its average not filled)
inline constexpr std::uint8_t derivative = 0x08;       // a distance derivative, not a distance
inline constexpr std::uint8_t presence = 0x10;         // look down: a target present
inline constexpr std::uint8_t pulses_overflow = 0x20;  // look down: more pulses than the count holds
inline constexpr std::uint8_t device_error = 0x40;     // an error number in the stream
inline constexpr std::uint8_t suspect = 0x80;          // marked by the quality checks (Sample.suspect_reason)
}  // namespace flag

// One row of the structured arrays read() and captures return (docs/python.md). The shared
// part fills time, distance_m (the reading, in metres), address, kind and the valid and
// suspect flags; the sample's family fills the rest, which stay NaN or 0 otherwise.
struct SampleRecord {
  double time;           // host receive time, seconds since the Unix epoch (UTC)
  double distance_m;     // metres; NaN when the sample holds none
  double intensity;      // pulse width in ns, or strength of the first target; NaN otherwise
  std::uint32_t pulses;  // look down: pulses between events; 0 when none
  std::uint16_t code;    // the result code as sent; 0 when none
  std::int16_t error;    // the device's error number; 0 when none
  std::int16_t address;  // bus address; -1 when the protocol has none
  std::uint8_t kind;     // rangekit::SampleKind
  std::uint8_t flags;    // flag::*
  std::uint8_t targets;  // targets in the sample's target list
};
SampleRecord to_record(const Sample& sample) noexcept;
// The records as a NumPy array (one copy, without the GIL).
py::array records_to_array(const std::vector<SampleRecord>& records);

// A sample or an event as its Python object (rangekit.Sample / rangekit.Event).
py::object to_python(StreamItem item);

// The Python stream object over a driver's MeasurementStream or a replay.
// The per-sample quality checks a stream applies, as `rangekit <family> stream` does
// (--max-speed, --drop-suspect; core/sample_quality.hpp).
struct StreamQuality {
  bool check = true;
  std::optional<double> max_speed_mps;  // none: the family default
  bool drop_suspect = false;
};

class Stream {
 public:
  Stream(SampleSourcePtr source, StreamQuality quality);
  ~Stream();
  py::object next_item();  // StopIteration at the end
  // The next item within `seconds` (none: for ever); None on timeout or at the end.
  py::object next_within(std::optional<double> seconds);
  // Up to `count` samples, or those of `duration` seconds, or until the end.
  py::array read(std::optional<std::size_t> count, std::optional<double> duration);
  py::list take_events();
  void stop();
  [[nodiscard]] bool finished() const;
  [[nodiscard]] bool waiting() const noexcept { return waiting_.load(); }
  [[nodiscard]] std::uint64_t lost() const;

 private:
  // Runs the quality checks on a sample; false when it is suspect and dropped.
  bool admit(StreamItem& item);
  // The next admitted item, from the batch at hand or the next one taken until `deadline`
  // (none: for ever); nothing when the deadline passed or the source finished.
  std::optional<StreamItem> next_admitted(std::optional<std::chrono::steady_clock::time_point> deadline);
  // Takes the source's next batch (everything it queued, one lock) into batch_, waiting
  // until `deadline` in short slices with the GIL released; between slices Python's signal
  // handlers run, so Ctrl-C raises KeyboardInterrupt here. False: the deadline passed or
  // the source finished and nothing is left.
  bool take_batch(std::optional<std::chrono::steady_clock::time_point> deadline);
  [[nodiscard]] bool batch_empty() const noexcept { return batch_next_ == batch_.size(); }
  // Takes the source's next batch without waiting beyond `timeout`; records the queue
  // dropped before it (counted just before the take) come first as one lost_records event,
  // since the queue drops its oldest: the gap lies before what it still held.
  bool take_from_source(std::chrono::milliseconds timeout);

  SampleSourcePtr source_;
  std::uint64_t lost_reported_ = 0;  // of source_->lost(), already handed out as events
  // The source's items taken but not handed out yet, from batch_next_ on: read(n) and the
  // iterator both hand them out before taking more, so every item comes out once, in order.
  std::vector<StreamItem> batch_;
  std::size_t batch_next_ = 0;
  std::optional<SampleChecker> checker_;
  bool drop_suspect_ = false;
  std::deque<StreamEvent> events_;  // met by read(), kept for take_events()
  std::atomic<bool> waiting_{false};
};

// The stream() keyword arguments both families share: check_quality, max_speed, drop_suspect.
StreamQuality stream_quality(bool check, std::optional<double> max_speed_mps, bool drop_suspect);

void init_samples(py::module_& module);
void init_streams(py::module_& module);
void init_families(py::module_& module);
void init_capture(py::module_& module);

}  // namespace rangekit::python
