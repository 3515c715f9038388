// A sensor's health as the service reports it: counts kept exact from every item
// its stream yields, a rate over the last seconds, and the link state.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "rangekit/core/sample.hpp"

namespace rangekit::hub {

struct SensorHealth {
  bool connected = false;
  double rate_hz = 0;         // samples a second over the last rate_window
  std::uint64_t records = 0;  // samples
  std::uint64_t errors = 0;   // samples that carry a device error (ULS $ER,n)
  std::map<int, std::uint64_t> errors_by_number;
  std::uint64_t no_signal = 0;        // LS5 65535 (§9.3)
  std::uint64_t suspect = 0;          // samples marked suspect (docs/reliability.md), dropped ones included
  std::uint64_t dropped_suspect = 0;  // of those, left out (drop_suspect in the site file)
  std::uint64_t lost = 0;             // records lost on the way (UDP gaps, full queues)
  std::uint64_t bad_frames = 0;
  std::uint64_t disconnects = 0;
  std::uint64_t reconnects = 0;
  std::optional<std::chrono::system_clock::time_point> last_seen;  // last sample
  std::string last_event;                                          // the last link event's message
};

class HealthTracker {
 public:
  static constexpr std::chrono::milliseconds bucket_width{100};
  static constexpr std::size_t bucket_count = 20;  // a 2 s window

  void record(const StreamItem& item, std::chrono::steady_clock::time_point now);
  void set_connected(bool connected, std::string message);
  // A suspect sample left out before it was published: counted, not a record.
  void record_dropped_suspect();
  [[nodiscard]] SensorHealth snapshot(std::chrono::steady_clock::time_point now) const;

 private:
  void count_sample(std::chrono::steady_clock::time_point now);
  [[nodiscard]] static std::int64_t bucket_of(std::chrono::steady_clock::time_point now);

  SensorHealth health_;
  std::array<std::uint32_t, bucket_count> buckets_{};
  std::int64_t newest_bucket_ = 0;
  std::optional<std::chrono::steady_clock::time_point> first_sample_;
};

}  // namespace rangekit::hub
