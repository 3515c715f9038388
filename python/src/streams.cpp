// Streams as Python iterators and NumPy readers. Every wait happens with the GIL
// released, in slices short enough that Ctrl-C (Python's SIGINT handler, run by
// PyErr_CheckSignals between slices) interrupts a blocking read at once.
#include <algorithm>
#include <mutex>
#include <thread>

#include "common.hpp"

namespace rangekit::python {
namespace {

using std::chrono::steady_clock;
// How long the GIL stays released before Python's signal handlers get a turn.
constexpr std::chrono::milliseconds signal_slice{50};
// How long a bulk read lets records gather in the queue before it drains them.
constexpr std::chrono::milliseconds batch_period{signal_slice};

std::chrono::milliseconds until(steady_clock::time_point end) {
  const auto left = std::chrono::ceil<std::chrono::milliseconds>(end - steady_clock::now());
  return std::max(left, std::chrono::milliseconds(0));
}

std::mutex& events_mutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

StreamQuality stream_quality(bool check, std::optional<double> max_speed_mps, bool drop_suspect) {
  if (max_speed_mps && !(*max_speed_mps > 0)) throw py::value_error("max_speed must be more than 0 m/s");
  if (drop_suspect && !check) throw py::value_error("drop_suspect needs check_quality");
  return StreamQuality{check, max_speed_mps, drop_suspect};
}

Stream::Stream(SampleSourcePtr source, StreamQuality quality)
    : source_(std::move(source)), drop_suspect_(quality.drop_suspect) {
  if (quality.check) checker_.emplace(QualitySettings{quality.max_speed_mps});
}

bool Stream::admit(StreamItem& item) {
  auto* sample = std::get_if<Sample>(&item);
  if (sample == nullptr || !checker_) return true;
  checker_->check(*sample);
  return !(sample->suspect && drop_suspect_);
}

bool Stream::take_from_source(std::chrono::milliseconds timeout) {
  const std::uint64_t lost_before = source_->lost();
  const bool got = source_->next_batch(batch_, timeout);
  batch_next_ = 0;
  if (got && lost_before > lost_reported_) {
    const std::uint64_t count = lost_before - lost_reported_;
    lost_reported_ = lost_before;
    batch_.insert(batch_.begin(),
                  StreamEvent{std::chrono::system_clock::now(), StreamEventKind::lost_records,
                              std::to_string(count) + " records lost: the stream's queue was full", count});
  }
  return got;
}

bool Stream::take_batch(std::optional<steady_clock::time_point> deadline) {
  while (true) {
    auto slice_end = steady_clock::now() + signal_slice;
    if (deadline) slice_end = std::min(slice_end, *deadline);
    // Read before waiting: a source that was finished then has nothing left once the
    // batch comes back empty, while one that finishes during the wait may still hand
    // over its last items.
    const bool was_finished = source_->finished();
    const bool got = without_gil([&] {
      waiting_ = true;
      const bool taken = take_from_source(until(slice_end));
      waiting_ = false;
      return taken;
    });
    if (got) return true;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // KeyboardInterrupt
    if (was_finished) return false;
    if (deadline && steady_clock::now() >= *deadline) return false;
  }
}

std::optional<StreamItem> Stream::next_admitted(std::optional<steady_clock::time_point> deadline) {
  while (true) {
    while (!batch_empty()) {
      StreamItem& item = batch_[batch_next_++];
      if (admit(item)) return std::move(item);
    }
    if (!take_batch(deadline)) return std::nullopt;
  }
}

Stream::~Stream() {
  // Joins the reader and leaves the device as the stream's own stop says.
  py::gil_scoped_release release;
  source_.reset();
}

py::object Stream::next_item() {
  if (!source_) throw py::stop_iteration();
  auto item = next_admitted(std::nullopt);
  if (!item) throw py::stop_iteration();
  return to_python(std::move(*item));
}

py::object Stream::next_within(std::optional<double> seconds) {
  if (!source_) return py::none();
  std::optional<steady_clock::time_point> deadline;
  if (seconds)
    deadline = steady_clock::now() +
               std::chrono::duration_cast<steady_clock::duration>(std::chrono::duration<double>(*seconds));
  auto item = next_admitted(deadline);
  if (!item) return py::none();
  return to_python(std::move(*item));
}

py::array Stream::read(std::optional<std::size_t> count, std::optional<double> duration) {
  if (!count && !duration) throw py::value_error("read() needs n (samples) or duration (seconds), or both");
  if (duration && !(*duration >= 0)) throw py::value_error("read(duration=...) must be 0 or more seconds");
  std::vector<SampleRecord> records;
  if (count) records.reserve(std::min<std::size_t>(*count, 1U << 20U));
  std::optional<steady_clock::time_point> deadline;
  if (duration)
    deadline = steady_clock::now() +
               std::chrono::duration_cast<steady_clock::duration>(std::chrono::duration<double>(*duration));
  const auto want_more = [&] { return !count || records.size() < *count; };
  bool ended = !source_;
  while (!ended && want_more()) {
    without_gil([&] {
      waiting_ = true;
      auto slice_end = steady_clock::now() + signal_slice;
      if (deadline) slice_end = std::min(slice_end, *deadline);
      while (want_more()) {
        if (batch_empty()) {
          const bool was_finished = source_->finished();  // before taking: see take_batch
          const bool got = take_from_source(std::chrono::milliseconds(0));
          if (!got) {
            ended = was_finished;
            if (ended || steady_clock::now() >= slice_end) break;
            // Nothing queued: let records gather for a batch period instead of waking for each
            // one (at 1 kHz that is 50 a wake-up, not 1); the array comes back at the end anyway.
            std::this_thread::sleep_for(
                std::min<steady_clock::duration>(batch_period, slice_end - steady_clock::now()));
            continue;
          }
        }
        // The whole batch in one go; what read(n) leaves of it stays for the next call.
        while (!batch_empty() && want_more()) {
          StreamItem& item = batch_[batch_next_++];
          if (!admit(item)) continue;  // suspect, and drop_suspect
          if (const auto* sample = std::get_if<Sample>(&item)) {
            records.push_back(to_record(*sample));
          } else {
            std::lock_guard lock(events_mutex());
            events_.push_back(std::get<StreamEvent>(std::move(item)));
          }
        }
        if (steady_clock::now() >= slice_end) break;
      }
      waiting_ = false;
      return 0;
    });
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // KeyboardInterrupt
    if (deadline && steady_clock::now() >= *deadline) break;
  }
  return records_to_array(records);
}

py::list Stream::take_events() {
  std::deque<StreamEvent> taken;
  {
    std::lock_guard lock(events_mutex());
    taken.swap(events_);
  }
  py::list events;
  for (StreamEvent& event : taken) events.append(py::cast(std::move(event)));
  return events;
}

void Stream::stop() {
  if (!source_) return;
  without_gil([&] {
    source_->stop();
    return 0;
  });
}

// The source's own flag only: another Python thread may ask while a read fills batch_ without the GIL.
bool Stream::finished() const { return !source_ || source_->finished(); }

std::uint64_t Stream::lost() const { return source_ ? source_->lost() : 0; }

void init_streams(py::module_& module) {
  py::class_<Stream>(module, "Stream",
                     "A measurement stream: iterate it for Sample and Event objects in order, or read() blocks of "
                     "samples as a NumPy structured array (rangekit.sample_dtype).")
      .def("__iter__", [](Stream& stream) -> Stream& { return stream; })
      .def("__next__", &Stream::next_item)
      .def("__enter__", [](Stream& stream) -> Stream& { return stream; })
      .def("__exit__", [](Stream& stream, const py::args&) { stream.stop(); })
      .def("next", &Stream::next_within, py::arg("timeout") = py::none(),
           "The next Sample or Event, waiting up to timeout seconds (None: for ever); None on timeout or "
           "at the end.")
      .def("read", &Stream::read, py::arg("n") = py::none(), py::kw_only(), py::arg("duration") = py::none(),
           "Samples as a NumPy structured array (rangekit.sample_dtype): up to n samples, or those arriving "
           "within duration seconds, whichever ends first (fewer when the stream ends). Events met on the way "
           "are kept for take_events(). The GIL is released while waiting; Ctrl-C raises KeyboardInterrupt.")
      .def("take_events", &Stream::take_events, "The events read() met since the last call, in order.")
      .def("stop", &Stream::stop, "Ends the stream (the device is left as the driver's stream stop says).")
      .def_property_readonly(
          "finished", &Stream::finished,
          "the stream has ended (what it queued before may still come out of read() and the iterator)")
      .def_property_readonly("lost", &Stream::lost, "records lost inside the stream (queue overflow, counter gaps)")
      .def_property_readonly("waiting", &Stream::waiting, "a read or next is waiting for the device right now");
}

}  // namespace rangekit::python
