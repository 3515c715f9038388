#include "mqtt/reading_window.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>

#include "rangekit/record/format.hpp"

namespace rangekit::mqtt {

std::optional<Distance> distance_of(const Sample& sample) {
  switch (sample.kind) {
    case SampleKind::uls_averaging:
      if (sample.distance_m) return Distance{*sample.distance_m, "m"};
      return std::nullopt;
    case SampleKind::uls_binning: {
      if (sample.targets.empty()) return std::nullopt;
      const auto nearest =
          std::min_element(sample.targets.begin(), sample.targets.end(),
                           [](const TargetHit& a, const TargetHit& b) { return a.distance_m < b.distance_m; });
      return Distance{nearest->distance_m, "m"};
    }
    case SampleKind::ls5_result:
      // 65534/65535 (§9.3) carry no distance: distance_mm is empty then.
      if (sample.distance_mm && sample.signal.value_or(SignalState::ok) == SignalState::ok) {
        return Distance{*sample.distance_mm, "mm"};
      }
      return std::nullopt;
    default:
      return std::nullopt;  // look-down, errors, LS5 derivatives: no distance
  }
}

ReadingWindow::ReadingWindow(double max_rate_hz) {
  if (max_rate_hz > 0) {
    period_ = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / max_rate_hz));
  }
}

std::optional<std::string> ReadingWindow::add(const Sample& sample, Clock::time_point now) {
  std::string own;
  record::append_jsonl(own, sample);
  if (!own.empty() && own.back() == '\n') own.pop_back();
  if (period_ == Clock::duration::zero()) return own;
  // Under the rate: a sample goes out at once when nothing is pending and the last message is a period old.
  if (count_ == 0 && lost_ == 0 && (!last_publish_ || now - *last_publish_ >= period_)) {
    last_publish_ = now;
    return own;
  }
  if (count_ == 0) first_time_ = sample.time;
  last_time_ = sample.time;
  ++count_;
  single_ = std::move(own);
  const auto distance = distance_of(sample);
  if (distance && sample.suspect) {
    ++suspect_;
  } else if (distance) {
    if (distances_ == 0) {
      min_ = max_ = distance->value;
    } else {
      min_ = std::min(min_, distance->value);
      max_ = std::max(max_, distance->value);
    }
    sum_ += distance->value;
    last_ = distance->value;
    unit_ = distance->unit;
    ++distances_;
  }
  if (sample.signal && *sample.signal != SignalState::ok) ++no_signal_;
  if (sample.device_error) ++errors_;
  if (sample.presence) presence_ = *sample.presence;
  return flush_due(now);
}

void ReadingWindow::add_lost(std::uint64_t count) { lost_ += count; }

std::optional<std::string> ReadingWindow::flush_due(Clock::time_point now) {
  if (count_ == 0 && lost_ == 0) return std::nullopt;
  if (period_ != Clock::duration::zero() && last_publish_ && now - *last_publish_ < period_) return std::nullopt;
  return close_window(now);
}

std::optional<std::string> ReadingWindow::close_window(Clock::time_point now) {
  std::string out;
  if (count_ == 1 && lost_ == 0) {
    out = std::move(single_);
  } else {
    nlohmann::json window{{"window", true}, {"count", count_},   {"unit", unit_},      {"no_signal", no_signal_},
                          {"lost", lost_},  {"errors", errors_}, {"suspect", suspect_}};
    std::string first;
    std::string last;
    record::append_iso_time(first, first_time_);
    record::append_iso_time(last, last_time_);
    window["start"] = count_ > 0 ? nlohmann::json(first) : nlohmann::json(nullptr);
    window["end"] = count_ > 0 ? nlohmann::json(last) : nlohmann::json(nullptr);
    window["distances"] = distances_;
    if (distances_ > 0) {
      window["min"] = min_;
      window["mean"] = sum_ / static_cast<double>(distances_);
      window["max"] = max_;
      window["last"] = last_;
    } else {
      window["min"] = window["mean"] = window["max"] = window["last"] = nullptr;
    }
    if (presence_) window["presence"] = *presence_;
    out = window.dump();
  }
  last_publish_ = now;
  count_ = distances_ = no_signal_ = lost_ = errors_ = suspect_ = 0;
  sum_ = 0;
  presence_.reset();
  single_.clear();
  return out;
}

}  // namespace rangekit::mqtt
