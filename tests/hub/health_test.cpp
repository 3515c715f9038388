// Per-sensor health: exact counts and a rate over whole 100 ms buckets of the last 2 s.
#include "rangekit/hub/health.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/uls/family.hpp"

#include <gtest/gtest.h>

namespace {

using namespace rangekit;
using namespace rangekit::hub;
using namespace std::chrono_literals;

TEST(Health, CountsEveryKindOfItem) {
  HealthTracker tracker;
  const auto t0 = std::chrono::steady_clock::time_point(1000s);
  tracker.record(StreamEvent{{}, StreamEventKind::connected, "up", 0}, t0);
  Sample error;
  error.device = "uls";
  error.set(uls::channel::error, 4);
  tracker.record(error, t0);
  tracker.record(error, t0);
  Sample no_signal;
  no_signal.device = "ls5";
  no_signal.set(ls5::channel::signal, ls5::SignalState::lost);
  tracker.record(no_signal, t0);
  // 65534, no measurement yet, is a record but no loss of the signal.
  Sample not_yet = no_signal;
  not_yet.set(ls5::channel::signal, ls5::SignalState::none_yet);
  tracker.record(not_yet, t0);
  tracker.record(StreamEvent{{}, StreamEventKind::lost_records, "gap", 168}, t0);
  tracker.record(StreamEvent{{}, StreamEventKind::bad_frame, "junk", 0}, t0);
  tracker.record(StreamEvent{{}, StreamEventKind::disconnected, "gone", 0}, t0);
  auto health = tracker.snapshot(t0);
  EXPECT_FALSE(health.connected);
  EXPECT_EQ(health.records, 4u);
  EXPECT_EQ(health.errors, 2u);
  EXPECT_EQ(health.errors_by_number.at(4), 2u);
  EXPECT_EQ(health.no_signal, 1u);
  EXPECT_EQ(health.lost, 168u);
  EXPECT_EQ(health.bad_frames, 1u);
  EXPECT_EQ(health.disconnects, 1u);
  EXPECT_EQ(health.last_event, "gone");
  tracker.record(StreamEvent{{}, StreamEventKind::reconnected, "back", 0}, t0);
  health = tracker.snapshot(t0);
  EXPECT_TRUE(health.connected);
  EXPECT_EQ(health.reconnects, 1u);
}

TEST(Health, RateIsSamplesPerSecondOverTheWindow) {
  HealthTracker tracker;
  const auto t0 = std::chrono::steady_clock::time_point(1000s);
  for (int i = 0; i < 400; ++i) tracker.record(Sample{}, t0 + i * 5ms);  // 200 Hz for 2 s
  EXPECT_NEAR(tracker.snapshot(t0 + 2s).rate_hz, 200.0, 0.5);
  EXPECT_NEAR(tracker.snapshot(t0 + 3s).rate_hz, 100.0, 10.0);  // half the window without samples
  EXPECT_EQ(tracker.snapshot(t0 + 10s).rate_hz, 0.0);           // silent: no stale rate
}

}  // namespace
