// The spike check (docs/reliability.md, "Suspect samples"): the allowance is the documents'
// stated accuracy, ULS §9 "±4 cm typical" and LS5 table 3.1 "±0.15 % of the range", typed
// in here; the readings are a still or moving target with a small honest scatter.
#include "rangekit/core/spike_check.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/uls/family.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <random>
#include <vector>

namespace rangekit::spike_check_test {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

const auto start = Clock::time_point(std::chrono::seconds(1000));

Sample uls_reading(double distance_m) {
  Sample sample;
  sample.device = "uls";
  sample.source = "/dev/ttyUSB0";
  sample.kind = uls::kind::averaging;
  sample.set(uls::channel::distance_m, distance_m);
  return sample;
}

// An LS5 record of a 100 mm range: formula 8.1, distance = code / 50000 × range.
Sample ls5_reading(int code) {
  Sample sample;
  sample.device = "ls5";
  sample.source = "/dev/ttyUSB1";
  sample.kind = ls5::kind::result;
  sample.set(ls5::channel::code, static_cast<std::uint16_t>(code));
  sample.set(ls5::channel::distance_mm, code * 100.0 / 50000.0);
  return sample;
}

std::vector<Sample> samples_of(const std::vector<StreamItem>& items) {
  std::vector<Sample> samples;
  for (const StreamItem& item : items) {
    if (const auto* sample = std::get_if<Sample>(&item)) samples.push_back(*sample);
  }
  return samples;
}

// Feeds `readings` `period` apart and lets the last one go; every sample released, in order.
std::vector<Sample> run(SpikeCheck& check, const std::vector<Sample>& readings, milliseconds period) {
  std::vector<StreamItem> out;
  auto now = start;
  for (const Sample& reading : readings) {
    check.push(reading, now, out);
    now += period;
  }
  check.release_all(out);
  return samples_of(out);
}

bool spike(const Sample& sample) { return sample.suspect && sample.suspect_reason.rfind("spike", 0) == 0; }

// A still LS5 at code 25000 with ±3 codes of scatter; 0.15 % of a 100 mm range is 75 codes.
std::vector<Sample> still_ls5(int count, std::mt19937& random) {
  std::uniform_int_distribution<int> scatter(-3, 3);
  std::vector<Sample> readings;
  for (int i = 0; i < count; ++i) readings.push_back(ls5_reading(25000 + scatter(random)));
  return readings;
}

TEST(SpikeCheck, L81_Ls5ADigitChangedBeyondTheAccuracyAndBackIsFlagged) {
  std::mt19937 random(1);
  auto readings = still_ls5(70, random);
  readings[40] = ls5_reading(25080);  // the tens digit's bit 3: 80 codes, over the 75 of table 3.1
  readings[50] = ls5_reading(24800);  // the hundreds digit: 200 codes
  readings[60] = ls5_reading(25040);  // 40 codes: within the accuracy, an honest reading could be there
  SpikeCheck check;
  const auto out = run(check, readings, milliseconds(1));
  ASSERT_EQ(out.size(), readings.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    EXPECT_EQ(out[i].get(ls5::channel::code), readings[i].get(ls5::channel::code)) << "the order changed at " << i;
    EXPECT_EQ(spike(out[i]), i == 40 || i == 50) << i << ": " << out[i].suspect_reason;
  }
}

TEST(SpikeCheck, U120_UlsEightCentimetresOutAndBackIsFlaggedThreeIsNot) {
  std::vector<Sample> readings;
  for (int i = 0; i < 60; ++i) readings.push_back(uls_reading(50.0 + 0.002 * (i % 3)));
  readings[35] = uls_reading(50.080);  // §9 ±4 cm typical: twice that
  readings[45] = uls_reading(50.030);  // within it
  SpikeCheck check;
  const auto out = run(check, readings, milliseconds(10));
  ASSERT_EQ(out.size(), readings.size());
  for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(spike(out[i]), i == 35) << i << ": " << out[i].suspect_reason;
}

// A target that steps (a new one in the beam) stays where it went: no spike.
TEST(SpikeCheck, ARealStepIsNoSpike) {
  std::mt19937 random(2);
  auto readings = still_ls5(30, random);
  for (int i = 0; i < 30; ++i) readings.push_back(ls5_reading(26000 + (i % 3)));
  SpikeCheck check;
  for (const Sample& sample : run(check, readings, milliseconds(1)))
    EXPECT_FALSE(spike(sample)) << sample.suspect_reason;
}

// Moving targets as fast as the noise bench's scenes: ULS 2 m/s at 100 readings a second,
// LS5 16 mm/s at 1000 a second (8 codes a reading on a 100 mm range), there and back.
TEST(SpikeCheck, MovingTargetsAreNoSpikes) {
  std::vector<Sample> uls;
  for (int i = 0; i < 400; ++i) uls.push_back(uls_reading(20.0 + 0.02 * (i < 200 ? i : 400 - i)));
  std::vector<Sample> ls5;
  for (int i = 0; i < 2000; ++i) ls5.push_back(ls5_reading(20000 + 8 * (i < 1000 ? i : 2000 - i) + (i * 7) % 5));
  SpikeCheck uls_check;
  for (const Sample& sample : run(uls_check, uls, milliseconds(10)))
    EXPECT_FALSE(sample.suspect) << sample.suspect_reason;
  SpikeCheck ls5_check;
  for (const Sample& sample : run(ls5_check, ls5, milliseconds(1)))
    EXPECT_FALSE(sample.suspect) << sample.suspect_reason;
}

// A moving target whose level (the median of the last readings) lags it by about the
// allowance, with the scatter of the stated accuracy: LS5 100 mm, 1.6 codes a reading (80
// codes behind), ±60 of the 75 codes of table 3.1. Readings near the allowance's edge, on
// either side of it, are no spikes.
TEST(SpikeCheck, AMovingTargetWhoseLevelLagsByTheAllowanceIsNoSpike) {
  std::mt19937 random(3);
  std::uniform_int_distribution<int> scatter(-60, 60);
  std::vector<Sample> readings;
  for (int i = 0; i < 6000; ++i) readings.push_back(ls5_reading(20000 + (i * 16) / 10 + scatter(random)));
  readings[3000] = ls5_reading(*readings[3000].get(ls5::channel::code) + 400);  // a changed digit still is one
  SpikeCheck check;
  const auto out = run(check, readings, milliseconds(1));
  ASSERT_EQ(out.size(), readings.size());
  for (std::size_t i = 0; i < out.size(); ++i)
    EXPECT_EQ(spike(out[i]), i == 3000) << i << ": " << out[i].suspect_reason;
}

// The ULS factory rate (PPM 1024 / PRF 2000: 512 ms) is slower than the hold limit: nothing
// waits, every reading leaves as it comes.
TEST(SpikeCheck, ASlowStreamIsNeverHeld) {
  SpikeCheck check;
  std::vector<StreamItem> out;
  auto now = start;
  for (int i = 0; i < 20; ++i) {
    check.push(uls_reading(50.0), now, out);
    EXPECT_EQ(out.size(), static_cast<std::size_t>(i + 1));
    now += milliseconds(512);
  }
  EXPECT_FALSE(check.holding());
}

StreamEvent event_of(StreamEventKind kind) { return StreamEvent{{}, kind, "", 0}; }

// A fast stream holds its newest reading: the next one, another kind of the same sensor, a
// link event or the hold limit lets it go, always before anything newer. A bad frame waits
// behind it, so that the reading is still judged by the next.
TEST(SpikeCheck, AHeldReadingLeavesFirstWhateverComesNext) {
  SpikeCheck check;
  std::vector<StreamItem> out;
  auto now = start;
  for (int i = 0; i < 5; ++i) {
    check.push(uls_reading(50.0 + i * 0.001), now, out);
    now += milliseconds(10);
  }
  ASSERT_TRUE(check.holding());
  ASSERT_EQ(out.size(), 4u);
  Sample error = uls_reading(0);
  error.kind = uls::kind::error;
  error.set(uls::channel::distance_m, std::nullopt);
  check.push(error, now, out);
  ASSERT_EQ(out.size(), 6u);
  EXPECT_EQ(std::get<Sample>(out[4]).get(uls::channel::distance_m), 50.004);
  EXPECT_EQ(std::get<Sample>(out[5]).kind, uls::kind::error);

  check.push(uls_reading(50.005), now, out);
  check.push(event_of(StreamEventKind::bad_frame), now, out);
  EXPECT_EQ(out.size(), 6u) << "the bad frame overtook the reading before it";
  check.push(uls_reading(50.006), now, out);
  ASSERT_EQ(out.size(), 8u);
  EXPECT_EQ(std::get<Sample>(out[6]).get(uls::channel::distance_m), 50.005);
  EXPECT_EQ(std::get<StreamEvent>(out[7]).kind, StreamEventKind::bad_frame);

  check.release_due(now + milliseconds(50), out);
  EXPECT_EQ(out.size(), 8u) << "released before the hold limit";
  check.release_due(now + milliseconds(101), out);
  ASSERT_EQ(out.size(), 9u);
  EXPECT_EQ(std::get<Sample>(out[8]).get(uls::channel::distance_m), 50.006);

  check.push(uls_reading(50.007), now, out);
  check.push(event_of(StreamEventKind::disconnected), now, out);
  ASSERT_EQ(out.size(), 11u);
  EXPECT_EQ(std::get<Sample>(out[9]).get(uls::channel::distance_m), 50.007);
  EXPECT_EQ(std::get<StreamEvent>(out[10]).kind, StreamEventKind::disconnected);
  EXPECT_FALSE(check.holding());
}

}  // namespace
}  // namespace rangekit::spike_check_test
