#include "rangekit/record/stream_loop.hpp"

#include <algorithm>
#include <utility>
#include <variant>
#include <vector>

#include "rangekit/core/family.hpp"
#include "rangekit/core/spike_check.hpp"
#include "rangekit/record/text_sink.hpp"

namespace rangekit::record {
namespace {

using Clock = std::chrono::steady_clock;

class StreamLoop {
 public:
  StreamLoop(SampleSource& source, const StreamLoopOptions& options, const std::atomic<bool>& stop_requested,
             const StreamObserver& observer)
      : source_(source), options_(options), stop_requested_(stop_requested), observer_(observer) {
    if (options_.quality) {
      checker_.emplace(*options_.quality);
      spikes_.emplace();
    }
  }

  StreamOutcome run() {
    if (auto opened = open_sinks(); !opened) return finish(StopReason::open_failed, std::move(opened).error());
    start_ = Clock::now();
    last_flush_ = start_;
    last_status_ = start_;
    if (options_.count && *options_.count == 0) return finish(StopReason::count_reached);
    while (true) {
      if (stop_requested_.load()) return finish(StopReason::interrupted);
      const auto now = Clock::now();
      auto timeout = options_.poll;
      if (options_.duration_s) {
        const auto limit =
            start_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(*options_.duration_s));
        if (now >= limit) return finish(StopReason::duration_reached);
        timeout = std::min(timeout, std::chrono::ceil<std::chrono::milliseconds>(limit - now));
      }
      // Read before waiting: a source that was finished then has nothing left
      // once next_batch() comes back empty, while one that finishes during the wait
      // may still hand over its last items.
      const bool was_finished = source_.finished();
      // One wake-up for everything the reader queued meanwhile: the items
      // are handled in order, exactly as if they had been taken one by one.
      if (source_.next_batch(batch_, timeout)) {
        const auto arrived = Clock::now();
        for (StreamItem& item : batch_) {
          if (auto written = std::visit([this, arrived](auto& value) { return handle(value, arrived); }, item);
              !written) {
            return finish(StopReason::write_failed, std::move(written).error());
          }
          if (options_.count && stats_.samples >= *options_.count) return finish(StopReason::count_reached);
        }
      } else if (was_finished) {
        return finish(StopReason::source_finished);
      }
      if (spikes_ && spikes_->holding()) {
        released_.clear();
        spikes_->release_due(Clock::now(), released_);
        if (auto written = emit_released(); !written)
          return finish(StopReason::write_failed, std::move(written).error());
        if (options_.count && stats_.samples >= *options_.count) return finish(StopReason::count_reached);
      }
      if (auto flushed = flush_if_due(); !flushed) return finish(StopReason::write_failed, std::move(flushed).error());
      report_status_if_due();
    }
  }

 private:
  Status open_sinks() {
    if (options_.write_output) {
      auto output = open_text_sink(options_.format, options_.out);
      if (!output) return std::move(output).error();
      output_ = std::move(*output);
    }
    if (!options_.capture.empty()) {
      auto capture = open_capture(options_.capture, options_.capture_options);
      if (!capture) return std::move(capture).error();
      capture_ = std::move(*capture);
    }
    return ok_status();
  }

  // The sample is the loop's own (taken from the batch): checked in place, then handed to the
  // spike check, which may hold it until the next reading (core/spike_check.hpp).
  Status handle(Sample& sample, Clock::time_point arrived) {
    if (!checker_) return write(sample);
    checker_->check(sample);
    released_.clear();
    spikes_->push(std::move(sample), arrived, released_);
    return emit_released();
  }

  Status handle(StreamEvent& event, Clock::time_point arrived) {
    if (!spikes_) return write(event);
    released_.clear();
    spikes_->push(std::move(event), arrived, released_);
    return emit_released();
  }

  // Writes what the spike check let go, in its order, stopping at the count.
  Status emit_released() {
    for (StreamItem& item : released_) {
      if (auto* sample = std::get_if<Sample>(&item)) {
        if (options_.count && stats_.samples >= *options_.count) break;
        if (auto written = write(*sample); !written) return written;
      } else if (auto written = write(std::get<StreamEvent>(item)); !written) {
        return written;
      }
    }
    return ok_status();
  }

  Status write(Sample& sample) {
    if (sample.suspect) {
      ++stats_.suspect;
      if (options_.drop_suspect) {
        ++stats_.dropped_suspect;
        return ok_status();
      }
    }
    ++stats_.samples;
    count_source(sample);
    if (value_of(sample, Quantity::error_number)) ++stats_.errors;  // the sensor said why it has no value
    if (output_) {
      if (auto status = output_->write(sample); !status) return status;
    }
    if (capture_) return capture_->write(sample);
    return ok_status();
  }

  Status write(const StreamEvent& event) {
    ++stats_.events;
    switch (event.kind) {
      case StreamEventKind::disconnected:
        ++stats_.disconnects;
        stats_.link_down = true;
        break;
      case StreamEventKind::connected:
      case StreamEventKind::reconnected:
        stats_.link_down = false;
        break;
      case StreamEventKind::bad_frame:
      case StreamEventKind::device_error:
        ++stats_.errors;
        break;
      case StreamEventKind::lost_records:
        lost_from_events_ += event.count;
        break;
      case StreamEventKind::polling:
        break;  // news, not trouble
    }
    update_lost();
    if (observer_.on_event) observer_.on_event(event);
    if (output_) {
      if (auto status = output_->write_event(event); !status) return status;
    }
    if (capture_) return capture_->write_event(event);
    return ok_status();
  }

  // The last source found is tried first: samples come in runs from one source.
  void count_source(const Sample& sample) {
    if (last_source_ < stats_.sources.size() && same_source(stats_.sources[last_source_], sample)) {
      ++stats_.sources[last_source_].samples;
      return;
    }
    for (last_source_ = 0; last_source_ < stats_.sources.size(); ++last_source_) {
      if (same_source(stats_.sources[last_source_], sample)) {
        ++stats_.sources[last_source_].samples;
        return;
      }
    }
    stats_.sources.push_back({sample.device + " " + std::string(sample.source.view()), 1});
  }
  static bool same_source(const SourceCount& known, const Sample& sample) {
    const std::string_view name = known.name;
    return name.size() == sample.device.size() + 1 + sample.source.view().size() && name.starts_with(sample.device) &&
           name.ends_with(sample.source.view());
  }

  void update_lost() { stats_.lost = std::max(lost_from_events_, source_.lost()); }

  Status flush_if_due() {
    if (Clock::now() - last_flush_ < options_.flush_interval) return ok_status();
    return flush_all();
  }

  Status flush_all() {
    last_flush_ = Clock::now();
    update_elapsed();
    Status result = ok_status();
    if (output_) {
      if (observer_.before_output_flush) observer_.before_output_flush();
      result = output_->flush();
      if (observer_.after_output_flush) observer_.after_output_flush(stats_);
    }
    // The capture keeps what it can even when the text output failed.
    if (capture_) {
      auto captured = capture_->flush();
      if (result && !captured) result = std::move(captured);
    }
    return result;
  }

  void report_status_if_due() {
    const auto now = Clock::now();
    if (!observer_.on_status || now - last_status_ < observer_.status_interval) return;
    last_status_ = now;
    update_elapsed();
    update_lost();
    observer_.on_status(stats_);
  }

  void update_elapsed() { stats_.elapsed_s = std::chrono::duration<double>(Clock::now() - start_).count(); }

  StreamOutcome finish(StopReason reason, std::optional<Error> error = std::nullopt) {
    if (reason != StopReason::source_finished) source_.stop();
    if (reason != StopReason::open_failed && reason != StopReason::write_failed && spikes_) {
      released_.clear();
      spikes_->release_all(released_);
      if (auto written = emit_released(); !written && !error) {
        reason = StopReason::write_failed;
        error = std::move(written).error();
      }
    }
    if (reason != StopReason::open_failed) {
      auto flushed = flush_all();
      if (!flushed && !error) {
        reason = StopReason::write_failed;
        error = std::move(flushed).error();
      }
    }
    output_.reset();
    capture_.reset();
    update_elapsed();
    update_lost();
    return StreamOutcome{reason, stats_, std::move(error)};
  }

  SampleSource& source_;
  const StreamLoopOptions& options_;
  const std::atomic<bool>& stop_requested_;
  const StreamObserver& observer_;
  SampleSinkPtr output_;
  std::unique_ptr<CaptureSink> capture_;
  StreamStats stats_;
  std::optional<SampleChecker> checker_;
  std::optional<SpikeCheck> spikes_;
  std::vector<StreamItem> released_;  // what the spike check let go, reused
  std::vector<StreamItem> batch_;     // what the source handed over last; its storage is reused
  std::uint64_t lost_from_events_ = 0;
  std::size_t last_source_ = 0;  // stats_.sources index of the latest sample's source
  Clock::time_point start_;
  Clock::time_point last_flush_;
  Clock::time_point last_status_;
};

}  // namespace

StreamOutcome run_stream_loop(SampleSource& source, const StreamLoopOptions& options,
                              const std::atomic<bool>& stop_requested, const StreamObserver& observer) {
  return StreamLoop(source, options, stop_requested, observer).run();
}

}  // namespace rangekit::record
