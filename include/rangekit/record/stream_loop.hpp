// The loop behind `rangekit uls|ls5 stream` and `replay`, without the CLI: samples from a
// SampleSource to a text sink and/or a capture until a count, a duration, the source's end,
// a stop request or a write failure. The CLI wraps it (src/cli/stream_runner.cpp).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/core/sample_quality.hpp"
#include "rangekit/record/capture.hpp"
#include "rangekit/record/sink.hpp"

namespace rangekit::record {

struct StreamLoopOptions {
  OutputFormat format = OutputFormat::text;
  bool write_output = true;                       // false: capture only, no formatted stream
  std::string out;                                // "" = standard output
  std::string capture;                            // "" = no capture
  std::optional<std::uint64_t> count;             // stop after this many samples
  std::optional<double> duration_s;               // stop after this many seconds
  std::chrono::milliseconds poll{50};             // longest wait on the source, so stops are prompt
  std::chrono::milliseconds flush_interval{100};  // text output and capture batches reach the file this often
  CaptureOptions capture_options;
  // Quality checks on each sample (docs/reliability.md); nullopt keeps the flags the samples
  // carry (a replay shows what was recorded).
  std::optional<QualitySettings> quality;
  bool drop_suspect = false;  // leave suspect samples out of the output and the capture
};

// One sensor of a stream that merges several (capture): its samples, so a silent one shows.
struct SourceCount {
  std::string name;  // "uls /dev/ttyUSB0": the family and where the samples came from
  std::uint64_t samples = 0;
};

struct StreamStats {
  std::uint64_t samples = 0;
  std::vector<SourceCount> sources;  // in the order each was first heard
  std::uint64_t events = 0;
  std::uint64_t errors = 0;  // device error samples/events and undecodable frames
  std::uint64_t lost = 0;    // lost records reported by events or the source
  std::uint64_t disconnects = 0;
  std::uint64_t suspect = 0;  // samples marked suspect (counted in `samples` unless dropped)
  std::uint64_t dropped_suspect = 0;
  double elapsed_s = 0;
  bool link_down = false;  // a disconnect without a reconnect after it
};

enum class StopReason { source_finished, count_reached, duration_reached, interrupted, open_failed, write_failed };

struct StreamOutcome {
  StopReason reason = StopReason::source_finished;
  StreamStats stats;
  std::optional<Error> error;  // for open_failed and write_failed
};

// What the CLI shows around the data; every callback is optional.
struct StreamObserver {
  std::function<void(const StreamEvent&)> on_event;
  std::function<void(const StreamStats&)> on_status;  // about twice a second
  std::function<void()> before_output_flush;          // e.g. clear a status line sharing the terminal
  std::function<void(const StreamStats&)> after_output_flush;
  std::chrono::milliseconds status_interval{500};
};

// Runs until one of the stop conditions; `stop_requested` is polled between items.
// On a write failure everything written before stays (committed capture batches).
StreamOutcome run_stream_loop(SampleSource& source, const StreamLoopOptions& options,
                              const std::atomic<bool>& stop_requested, const StreamObserver& observer = {});

}  // namespace rangekit::record
