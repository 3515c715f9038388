// Replay of a SQLite capture as a SampleSource: the captured samples and events
// in the order they were written, either at the recorded pace (the gaps between
// receive times are kept, divided by `speed`) or as fast as the consumer reads.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>

#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"

namespace rangekit::record {

struct ReplayOptions {
  double speed = 1.0;  // 1 = recorded pace, 2 = twice as fast; <= 0 = full speed (no waiting)
  std::string device;  // "" = every sample; "uls" or "ls5" = only that family (events always pass)
};

// Recorded pace: an item received `recorded_gap` after the first item of the
// replay is due this long after the first item came out (gap / speed; never
// negative). The replay waits for it; tests check the rule here, without a clock.
[[nodiscard]] std::chrono::nanoseconds replay_delay(std::chrono::nanoseconds recorded_gap, double speed);

// Opens the capture read-only; a missing file, a non-capture or a corrupt file
// is Errc::io naming it.
Result<SampleSourcePtr> open_replay(const std::string& path, const ReplayOptions& options);
inline Result<SampleSourcePtr> open_replay(const std::string& path, double speed) {
  return open_replay(path, ReplayOptions{speed, {}});
}

// Every sample (of `device` only, unless empty) and every event of a capture, in the
// order they were written, handed over as the file is read: no queue, no thread, and
// one Sample reused for every row (copy what you keep). For bulk reads (the Python
// package's rangekit.capture). A capture damaged after opening ends with one bad_frame
// event saying why, as in open_replay; opening fails as open_replay does, except that the
// integrity check (PRAGMA quick_check) runs on a second thread while the rows are read:
// when it fails, the error is returned after the callbacks have seen what could be read,
// and the caller must discard it.
// At least as many as the samples for_each_in_capture hands over (the span of their
// sequence numbers, which they share with the events), read from the ends of the table
// without a scan: a bulk reader allocates once. Opening fails as open_replay does, but
// without the integrity check (for_each_in_capture runs it).
Result<std::size_t> capture_sample_bound(const std::string& path);

// Which fields of the samples for_each_in_capture fills: all of them, or those of an
// array row (rangekit.capture in Python): `source`, `resolution_mm` and `suspect_reason`
// are left empty. An array read takes the samples from the file's pages without SQLite's
// row engine when the file qualifies (docs/capture.md, "Direct reading of the samples"):
// same samples and events, and damage to the samples' pages is an error naming the page
// instead of quick_check's verdict.
enum class CaptureFields { all, array };

Status for_each_in_capture(const std::string& path, std::string_view device,
                           const std::function<void(const Sample&)>& on_sample,
                           const std::function<void(StreamEvent&&)>& on_event,
                           CaptureFields fields = CaptureFields::all);

}  // namespace rangekit::record
