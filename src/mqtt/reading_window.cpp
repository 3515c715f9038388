#include "mqtt/reading_window.hpp"

#include <nlohmann/json.hpp>

#include "rangekit/core/family.hpp"
#include "rangekit/record/format.hpp"

namespace rangekit::mqtt {

ReadingWindow::ReadingWindow(double max_rate_hz) {
  if (max_rate_hz > 0) {
    period_ = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / max_rate_hz));
  }
}

namespace {

std::string message_of(const Sample& sample) {
  std::string own;
  record::append_jsonl(own, sample);
  if (!own.empty() && own.back() == '\n') own.pop_back();
  return own;
}

}  // namespace

std::optional<std::string> ReadingWindow::add(const Sample& sample, Clock::time_point now) {
  if (period_ == Clock::duration::zero()) return message_of(sample);
  // Under the rate: a sample goes out at once when nothing is pending and the last message is a period old.
  if (count_ == 0 && lost_ == 0 && (!last_publish_ || now - *last_publish_ >= period_)) {
    last_publish_ = now;
    return message_of(sample);
  }
  // Above it, a window's first sample is kept and written only if it stays alone: a 1 kHz
  // sensor at 10 messages a second would otherwise be formatted a thousand times for ten.
  if (count_ == 0) {
    first_time_ = sample.time;
    single_ = sample;
  }
  last_time_ = sample.time;
  ++count_;
  const auto reading = reading_of(sample);
  if (reading && sample.suspect) {
    ++suspect_;
  } else if (reading) {
    readings_.add(*reading);
  }
  if (value_of(sample, Quantity::signal).value_or(0) != 0) ++no_signal_;
  if (value_of(sample, Quantity::error_number)) ++errors_;
  if (const auto present = value_of(sample, Quantity::presence)) presence_ = *present != 0;
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
  if (count_ == 1 && lost_ == 0 && single_) {
    out = message_of(*single_);
  } else {
    nlohmann::json window{{"window", true}, {"count", count_},   {"unit", readings_.unit()}, {"no_signal", no_signal_},
                          {"lost", lost_},  {"errors", errors_}, {"suspect", suspect_}};
    std::string first;
    std::string last;
    record::append_iso_time(first, first_time_);
    record::append_iso_time(last, last_time_);
    window["start"] = count_ > 0 ? nlohmann::json(first) : nlohmann::json(nullptr);
    window["end"] = count_ > 0 ? nlohmann::json(last) : nlohmann::json(nullptr);
    window["readings"] = readings_.count();
    if (!readings_.empty()) {
      window["channel"] = readings_.channel()->key;
      window["min"] = readings_.min();
      window["mean"] = readings_.mean();
      window["max"] = readings_.max();
      window["last"] = readings_.last();
    } else {
      window["channel"] = window["min"] = window["mean"] = window["max"] = window["last"] = nullptr;
    }
    if (presence_) window["presence"] = *presence_;
    out = window.dump();
  }
  last_publish_ = now;
  count_ = no_signal_ = lost_ = errors_ = suspect_ = 0;
  readings_.clear();
  presence_.reset();
  single_.reset();
  return out;
}

}  // namespace rangekit::mqtt
