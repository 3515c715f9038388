#include "rangekit/hub/health.hpp"

#include <algorithm>
#include <variant>

#include "rangekit/core/family.hpp"

namespace rangekit::hub {

std::int64_t HealthTracker::bucket_of(std::chrono::steady_clock::time_point now) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() / bucket_width.count();
}

void HealthTracker::count_sample(std::chrono::steady_clock::time_point now) {
  const std::int64_t bucket = bucket_of(now);
  if (!first_sample_) first_sample_ = now;
  // Empty the buckets the clock moved past since the last sample.
  for (std::int64_t b = newest_bucket_ + 1; b <= bucket && b <= newest_bucket_ + std::int64_t{bucket_count}; ++b) {
    buckets_[static_cast<std::size_t>(b) % bucket_count] = 0;
  }
  if (bucket > newest_bucket_ + std::int64_t{bucket_count}) buckets_.fill(0);
  newest_bucket_ = std::max(newest_bucket_, bucket);
  ++buckets_[static_cast<std::size_t>(bucket) % bucket_count];
}

void HealthTracker::record_dropped_suspect() {
  ++health_.suspect;
  ++health_.dropped_suspect;
}

void HealthTracker::record(const StreamItem& item, std::chrono::steady_clock::time_point now) {
  if (const auto* sample = std::get_if<Sample>(&item)) {
    ++health_.records;
    health_.last_seen = sample->time;
    if (const auto number = value_of(*sample, Quantity::error_number)) {
      ++health_.errors;
      ++health_.errors_by_number[static_cast<int>(*number)];
    }
    if (signal_lost(*sample)) ++health_.no_signal;
    if (sample->suspect) ++health_.suspect;
    count_sample(now);
    return;
  }
  const auto& event = std::get<StreamEvent>(item);
  health_.last_event = event.message;
  switch (event.kind) {
    case StreamEventKind::connected:
      health_.connected = true;
      break;
    case StreamEventKind::disconnected:
      health_.connected = false;
      ++health_.disconnects;
      break;
    case StreamEventKind::reconnected:
      health_.connected = true;
      ++health_.reconnects;
      break;
    case StreamEventKind::bad_frame:
      ++health_.bad_frames;
      break;
    case StreamEventKind::lost_records:
      health_.lost += event.count;
      break;
    case StreamEventKind::device_error:
    case StreamEventKind::polling:
      break;
  }
}

void HealthTracker::set_connected(bool connected, std::string message) {
  health_.connected = connected;
  health_.last_event = std::move(message);
}

SensorHealth HealthTracker::snapshot(std::chrono::steady_clock::time_point now) const {
  SensorHealth health = health_;
  const std::int64_t current = bucket_of(now);
  // Whole buckets only: the current, partly filled one is left out of the rate.
  std::uint64_t counted = 0;
  std::int64_t buckets = 0;
  for (std::int64_t b = current - std::int64_t{bucket_count} + 1; b < current; ++b) {
    if (first_sample_ && b < bucket_of(*first_sample_)) continue;  // before the stream began
    ++buckets;
    if (b > newest_bucket_ || b <= newest_bucket_ - std::int64_t{bucket_count}) continue;
    counted += buckets_[static_cast<std::size_t>(b) % bucket_count];
  }
  const double seconds = static_cast<double>(buckets) * static_cast<double>(bucket_width.count()) / 1000.0;
  health.rate_hz = seconds > 0 ? static_cast<double>(counted) / seconds : 0;
  return health;
}

}  // namespace rangekit::hub
