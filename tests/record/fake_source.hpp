// Hand-built samples and a scripted SampleSource for the record tests.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <utility>
#include <vector>

#include "rangekit/core/sample.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/uls/family.hpp"

namespace rangekit::record::testing {

using namespace std::chrono_literals;

// 2026-11-26T01:02:03.456Z plus `offset`.
inline std::chrono::system_clock::time_point at(std::chrono::milliseconds offset = 0ms) {
  using namespace std::chrono;
  return sys_days{year{2026} / November / 26} + 1h + 2min + 3s + 456ms + offset;
}

inline Sample uls_averaging(std::chrono::milliseconds offset = 0ms) {
  Sample sample;
  sample.time = at(offset);
  sample.device = "uls";
  sample.source = "/dev/ttyUSB0";
  sample.address = 3;
  sample.kind = uls::kind::averaging;
  sample.set(uls::channel::distance_m, 12.345);
  sample.set(uls::channel::pulse_width_ps, 18000);
  return sample;
}

inline Sample uls_binning() {
  Sample sample;
  sample.time = at();
  sample.device = "uls";
  sample.source = "/dev/ttyUSB0";
  sample.kind = uls::kind::binning;
  sample.targets = {{4.572, 42}, {7.1, 13}};
  return sample;
}

inline Sample uls_look_down() {
  Sample sample;
  sample.time = at();
  sample.device = "uls";
  sample.source = "/dev/ttyUSB1";
  sample.address = 0;
  sample.kind = uls::kind::look_down;
  sample.set(uls::channel::presence, true);
  sample.set(uls::channel::pulses_between_events, 250);
  return sample;
}

// §8 "If time exceeds this value, the output will be set to 0000 hex signifying maximum time
// occurred": more than 65535 pulses between the edges (U88).
inline Sample uls_look_down_overflow() {
  Sample sample = uls_look_down();
  sample.set(uls::channel::pulses_between_events, std::nullopt);
  sample.set(uls::channel::pulses_overflow, true);
  return sample;
}

inline Sample uls_error() {
  Sample sample;
  sample.time = at();
  sample.device = "uls";
  sample.source = "/dev/ttyUSB0";
  sample.address = 3;
  sample.kind = uls::kind::error;
  sample.set(uls::channel::error, 4);
  return sample;
}

inline Sample ls5_result(std::uint16_t code, std::optional<double> distance_mm, ls5::SignalState signal) {
  Sample sample;
  sample.time = at();
  sample.device = "ls5";
  sample.source = "udp:127.0.0.1:5000";
  sample.kind = ls5::kind::result;
  sample.set(ls5::channel::code, code);
  sample.set(ls5::channel::distance_mm, distance_mm);
  sample.set(ls5::channel::signal, signal);
  return sample;
}

inline StreamEvent event(StreamEventKind kind, std::string message, std::uint64_t count = 0) {
  StreamEvent result;
  result.time = at();
  result.kind = kind;
  result.message = std::move(message);
  result.count = count;
  return result;
}

// Hands out the scripted items in order; finished once they are all taken,
// unless `endless`, in which case it waits (up to the timeout) for stop().
class FakeSource final : public SampleSource {
 public:
  explicit FakeSource(std::vector<StreamItem> items, bool endless = false)
      : items_(items.begin(), items.end()), endless_(endless) {}

  std::optional<StreamItem> next(std::chrono::milliseconds timeout) override {
    std::unique_lock lock(mutex_);
    if (!items_.empty() && !stopped_) {
      auto item = std::move(items_.front());
      items_.pop_front();
      return item;
    }
    if (endless_) wake_.wait_for(lock, timeout, [this] { return stopped_; });
    return std::nullopt;
  }
  [[nodiscard]] bool finished() const override {
    std::lock_guard lock(mutex_);
    return stopped_ || (!endless_ && items_.empty());
  }
  void stop() override {
    {
      std::lock_guard lock(mutex_);
      stopped_ = true;
    }
    wake_.notify_all();
  }
  [[nodiscard]] bool stopped() const {
    std::lock_guard lock(mutex_);
    return stopped_;
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<StreamItem> items_;
  bool endless_;
  bool stopped_ = false;
};

}  // namespace rangekit::record::testing
