// SQLite capture: an append-only file holding every sample and event of one or
// more sessions (schema in docs/capture.md). Writes are batched into
// transactions (WAL, synchronous=NORMAL): a kill -9 loses at most the batch not
// yet committed and never corrupts the file; a full disk fails the current batch
// with a clear error and leaves every committed batch readable.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "rangekit/record/sink.hpp"

namespace rangekit::record {

// Version of the capture schema, stored in the meta table.
inline constexpr int capture_format_version = 1;

struct CaptureOptions {
  std::chrono::milliseconds batch_interval{200};  // commit when the open batch is this old...
  std::size_t batch_samples = 1000;               // ...or holds this many items
  std::int64_t max_page_count = 0;                // > 0: SQLite page limit (tests simulate a full disk)
};

class CaptureSink : public SampleSink {
 public:
  // Samples of this session that are committed (durable against kill -9).
  [[nodiscard]] virtual std::uint64_t committed_samples() const = 0;
  [[nodiscard]] virtual const std::string& path() const = 0;
};

// Creates the capture, or appends a new session to an existing one. A file that
// is not a rangekit capture (another SQLite database, text, a corrupt file) is
// refused with Errc::io naming it, and left untouched.
Result<std::unique_ptr<CaptureSink>> open_capture(const std::string& path, const CaptureOptions& options = {});

}  // namespace rangekit::record
