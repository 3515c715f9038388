#include "rangekit/record/replay.hpp"

#include <gtest/gtest.h>

#include "rangekit/ls5/family.hpp"
#include "rangekit/record/capture.hpp"
#include "rangekit/record/format.hpp"
#include "rangekit/record/stream_loop.hpp"
#include "rangekit/uls/family.hpp"
#include "record/fake_source.hpp"
#include "record/temp_dir.hpp"

namespace rangekit::record {
namespace {

using namespace testing;
using SteadyTime = std::chrono::steady_clock::time_point;

void capture_samples(const std::string& path, const std::vector<Sample>& samples) {
  auto capture = open_capture(path);
  ASSERT_TRUE(capture.ok()) << capture.error().message;
  for (const auto& sample : samples) ASSERT_TRUE((*capture)->write(sample).ok());
}

// When each item came out of the replay, on the steady clock.
std::vector<SteadyTime> arrival_times(SampleSource& source) {
  std::vector<SteadyTime> times;
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (!source.finished() && std::chrono::steady_clock::now() < deadline) {
    if (source.next(50ms)) times.push_back(std::chrono::steady_clock::now());
  }
  return times;
}

// The pacing rule itself, without a clock: the gap to the first item divided by speed.
TEST(Replay, DelayIsTheRecordedGapDividedBySpeed) {
  EXPECT_EQ(replay_delay(300ms, 1.0), 300ms);
  EXPECT_EQ(replay_delay(1200ms, 1.0), 1200ms);
  EXPECT_EQ(replay_delay(1000ms, 4.0), 250ms);
  EXPECT_EQ(replay_delay(1000ms, 0.5), 2000ms);
  EXPECT_EQ(replay_delay(-5ms, 1.0), 0ms);   // a clock step back in the capture never waits
  EXPECT_EQ(replay_delay(3600s, 0.0), 0ms);  // full speed
}

// On the real clock only "never early" can be asserted: a loaded machine may
// deliver late, so there is no upper bound here (the rule is tested above).
TEST(Replay, RecordedPaceNeverDeliversEarly) {
  TempDir dir;
  const auto path = dir.file("paced.sqlite");
  capture_samples(path, {uls_averaging(0ms), uls_averaging(300ms), uls_averaging(600ms), uls_averaging(1200ms)});
  auto source = open_replay(path, 1.0);
  ASSERT_TRUE(source.ok());
  const auto times = arrival_times(**source);
  ASSERT_EQ(times.size(), 4u);
  EXPECT_GE(times[1] - times[0], 290ms);  // small slack for clock rounding
  EXPECT_GE(times[2] - times[0], 590ms);
  EXPECT_GE(times[3] - times[0], 1190ms);
}

TEST(Replay, SpeedNeverDeliversEarly) {
  TempDir dir;
  const auto path = dir.file("fast.sqlite");
  capture_samples(path, {uls_averaging(0ms), uls_averaging(1000ms)});
  auto source = open_replay(path, 4.0);
  ASSERT_TRUE(source.ok());
  const auto times = arrival_times(**source);
  ASSERT_EQ(times.size(), 2u);
  EXPECT_GE(times[1] - times[0], 240ms);
}

// Items an hour apart at full speed: a replay that waited would time out the
// short reads below, whatever the machine's load.
TEST(Replay, FullSpeedDoesNotWait) {
  TempDir dir;
  const auto path = dir.file("full.sqlite");
  capture_samples(path, {uls_averaging(0ms), uls_averaging(3600s), uls_averaging(7200s)});
  auto source = open_replay(path, 0.0);
  ASSERT_TRUE(source.ok());
  for (int item = 0; item < 3; ++item) EXPECT_TRUE((*source)->next(1ms).has_value()) << "item " << item;
  EXPECT_TRUE((*source)->finished());
}

TEST(Replay, StopEndsAWaitAtOnce) {
  TempDir dir;
  const auto path = dir.file("stop.sqlite");
  capture_samples(path, {uls_averaging(0ms), uls_averaging(3600s)});
  auto source = open_replay(path, 1.0);
  ASSERT_TRUE(source.ok());
  ASSERT_TRUE((*source)->next(1000ms).has_value());
  EXPECT_FALSE((*source)->next(10ms).has_value());  // an hour away
  EXPECT_FALSE((*source)->finished());
  (*source)->stop();
  EXPECT_TRUE((*source)->finished());
  EXPECT_FALSE((*source)->next(10s).has_value());
}

TEST(Replay, DeviceFilterKeepsOneFamilyAndEveryEvent) {
  TempDir dir;
  const auto path = dir.file("filter.sqlite");
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok());
    ASSERT_TRUE((*capture)->write(uls_averaging()).ok());
    ASSERT_TRUE((*capture)->write_event(event(StreamEventKind::disconnected, "gone")).ok());
    ASSERT_TRUE((*capture)->write(ls5_result(7, 1.0, ls5::SignalState::ok)).ok());
  }
  auto source = open_replay(path, ReplayOptions{0.0, "ls5"});
  ASSERT_TRUE(source.ok());
  auto first = (*source)->next(1s);
  auto second = (*source)->next(1s);
  ASSERT_TRUE(first && second);
  EXPECT_TRUE(std::holds_alternative<StreamEvent>(*first));
  EXPECT_EQ(std::get<Sample>(*second).device, "ls5");
  EXPECT_FALSE((*source)->next(10ms).has_value());
  EXPECT_TRUE((*source)->finished());
}

TEST(Replay, MissingFileIsAnIoErrorNamingIt) {
  const auto source = open_replay("/nonexistent-dir/capture.sqlite", 0.0);
  ASSERT_FALSE(source.ok());
  EXPECT_EQ(source.error().code, Errc::io);
  EXPECT_NE(source.error().message.find("/nonexistent-dir/capture.sqlite"), std::string::npos);
}

// The live stream written to a file and captured, then the capture replayed
// into another file: the two must be the same bytes.
void expect_replay_identical_to_live(OutputFormat format) {
  TempDir dir;
  const auto live = dir.file("live.out");
  const auto replayed = dir.file("replayed.out");
  const auto capture = dir.file("capture.sqlite");
  auto binning_with_odd_values = uls_binning();
  binning_with_odd_values.targets.push_back({0.1 + 0.2, 4294967295u});
  auto averaging = uls_averaging(1ms);
  averaging.set(uls::channel::distance_m, 1.0 / 3.0);
  // L60, L63: a 0.5/5 sensor's 0.0001 mm (table 5.1) and a derivative keep their digits.
  auto fine = ls5_result(21124, 2.1124, ls5::SignalState::ok);
  fine.set(ls5::channel::resolution_mm, 0.0001);
  auto derivative = ls5_result(25050, std::nullopt, ls5::SignalState::ok);
  derivative.kind = ls5::kind::derivative;
  derivative.set(ls5::channel::derivative_mm, 0.1);
  derivative.set(ls5::channel::resolution_mm, 0.001);
  FakeSource source({averaging, binning_with_odd_values, event(StreamEventKind::bad_frame, "half \"frame\""),
                     // The switch to polling is an event, replayed as one.
                     event(StreamEventKind::polling, "/dev/ttyUSB0: polling with BM every 50 ms"), uls_look_down(),
                     uls_look_down_overflow(), uls_error(), ls5_result(12345, 1234.5, ls5::SignalState::ok),
                     ls5_result(65534, std::nullopt, ls5::SignalState::none_yet), fine, derivative});
  const std::atomic<bool> stop{false};
  StreamLoopOptions options;
  options.format = format;
  options.out = live;
  options.capture = capture;
  ASSERT_EQ(run_stream_loop(source, options, stop).reason, StopReason::source_finished);

  auto replay = open_replay(capture, 0.0);
  ASSERT_TRUE(replay.ok());
  options.out = replayed;
  options.capture.clear();
  ASSERT_EQ(run_stream_loop(**replay, options, stop).reason, StopReason::source_finished);
  const auto live_bytes = read_file(live);
  EXPECT_GT(live_bytes.size(), 100u);
  EXPECT_NE(live_bytes.find("2.1124"), std::string::npos) << live_bytes;
  EXPECT_NE(live_bytes.find("0.100"), std::string::npos) << live_bytes;
  EXPECT_EQ(read_file(replayed), live_bytes);
}

TEST(Replay, JsonlIsByteIdenticalToTheLiveStream) { expect_replay_identical_to_live(OutputFormat::jsonl); }
}  // namespace
}  // namespace rangekit::record

namespace rangekit::record {
namespace {

// One text per item, as `stream --format jsonl` writes it.
std::string item_text(const StreamItem& item) {
  std::string text;
  std::visit([&text](const auto& value) { append_jsonl(text, value); }, item);
  return text;
}

std::vector<std::string> replayed_texts(const std::string& path, const std::string& device) {
  auto source = open_replay(path, ReplayOptions{0.0, device});
  EXPECT_TRUE(source.ok());
  std::vector<std::string> texts;
  if (!source.ok()) return texts;
  while (auto item = (*source)->next(0ms)) texts.push_back(item_text(*item));
  return texts;
}

std::vector<std::string> bulk_texts(const std::string& path, const std::string& device) {
  std::vector<std::string> texts;
  const auto read = for_each_in_capture(
      path, device, [&](const Sample& sample) { texts.push_back(item_text(StreamItem(sample))); },
      [&](StreamEvent&& event) { texts.push_back(item_text(StreamItem(std::move(event)))); });
  EXPECT_TRUE(read.ok()) << read.error().message;
  return texts;
}

// The bulk reader reuses one Sample for every row: a row must never keep a field of the row
// before it (targets after a binning row, a reason after a suspect one, an overflow flag).
TEST(CaptureBulkRead, GivesWhatTheReplayGivesInTheSameOrder) {
  TempDir dir;
  const auto path = dir.file("bulk.sqlite");
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok());
    auto suspect = ls5_result(34845, 69.69, ls5::SignalState::ok);
    suspect.suspect = true;
    suspect.suspect_reason = "jump: 20 mm in 1 ms";
    const std::vector<StreamItem> items{uls_binning(),
                                        uls_averaging(1ms),
                                        event(StreamEventKind::disconnected, "gone"),
                                        uls_look_down_overflow(),
                                        uls_look_down(),
                                        suspect,
                                        ls5_result(24845, 49.69, ls5::SignalState::ok),
                                        ls5_result(65535, std::nullopt, ls5::SignalState::lost),
                                        uls_error()};
    for (const auto& item : items) {
      if (const auto* sample = std::get_if<Sample>(&item)) {
        ASSERT_TRUE((*capture)->write(*sample).ok());
      } else {
        ASSERT_TRUE((*capture)->write_event(std::get<StreamEvent>(item)).ok());
      }
    }
  }
  for (const std::string device : {"", "uls", "ls5"}) {
    const auto replayed = replayed_texts(path, device);
    EXPECT_EQ(bulk_texts(path, device), replayed) << "device '" << device << "'";
    EXPECT_EQ(replayed.size(), device.empty() ? 9U : device == "uls" ? 6U : 4U);
  }
}

// CaptureFields::array (the Python arrays' reader) leaves out what an array row has no
// column for: source, resolution_mm and suspect_reason come back empty, the rest as always.
TEST(CaptureBulkRead, ArrayFieldsLeaveOutSourceResolutionAndSuspectReason) {
  TempDir dir;
  const auto path = dir.file("array.sqlite");
  auto suspect = ls5_result(34845, 69.69, ls5::SignalState::ok);
  suspect.suspect = true;
  suspect.suspect_reason = "jump: 20 mm in 1 ms";
  suspect.set(ls5::channel::resolution_mm, 0.002);
  capture_samples(path,
                  {uls_binning(), suspect, uls_look_down_overflow(), ls5_result(24845, 49.69, ls5::SignalState::ok)});
  const auto read = [&path](CaptureFields fields) {
    std::vector<Sample> samples;
    const auto status = for_each_in_capture(
        path, "", [&](const Sample& sample) { samples.push_back(sample); }, [](StreamEvent&&) {}, fields);
    EXPECT_TRUE(status.ok()) << status.error().message;
    return samples;
  };
  auto expected = read(CaptureFields::all);
  ASSERT_EQ(expected.size(), 4U);
  EXPECT_FALSE(expected[1].source.empty());
  EXPECT_EQ(expected[1].suspect_reason, "jump: 20 mm in 1 ms");
  EXPECT_EQ(expected[1].get(ls5::channel::resolution_mm), 0.002);
  for (Sample& sample : expected) {
    sample.source.clear();
    sample.set(ls5::channel::resolution_mm, std::nullopt);
    sample.suspect_reason.clear();
  }
  EXPECT_EQ(read(CaptureFields::array), expected);
}

TEST(CaptureBulkRead, AMissingFileIsAnIoErrorNamingIt) {
  const auto read = for_each_in_capture(
      "/nonexistent-dir/capture.sqlite", "", [](const Sample&) {}, [](StreamEvent&&) {});
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error().code, Errc::io);
  EXPECT_NE(read.error().message.find("/nonexistent-dir/capture.sqlite"), std::string::npos);
}

// The integrity check runs beside the scan in the bulk reader: a damaged file is still
// refused with an error that names it, never read as if it were whole.
TEST(CaptureBulkRead, ACorruptCaptureIsAnIoErrorNamingIt) {
  TempDir dir;
  const auto path = dir.file("corrupt.sqlite");
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok());
    for (int i = 0; i < 500; ++i) ASSERT_TRUE((*capture)->write(uls_averaging(std::chrono::milliseconds(i))).ok());
  }
  auto content = read_file(path);
  ASSERT_GT(content.size(), 4 * 4096U);
  for (std::size_t i = 2 * 4096; i < 3 * 4096; ++i) content[i] = static_cast<char>(0xA5);  // a b-tree page
  write_file(path, content);
  std::size_t samples = 0;
  const auto read = for_each_in_capture(
      path, "", [&](const Sample&) { ++samples; }, [](StreamEvent&&) {});
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error().code, Errc::io);
  EXPECT_NE(read.error().message.find("corrupt"), std::string::npos) << read.error().message;
  EXPECT_NE(read.error().message.find(path), std::string::npos) << read.error().message;
}

// Samples and events share one sequence (1, 2, 3, ... in the order written): the span of
// the samples' numbers is at least their count, whichever device is asked for.
TEST(CaptureBulkRead, SampleBoundIsTheSpanOfTheSamplesSequenceNumbers) {
  TempDir dir;
  const auto path = dir.file("bound.sqlite");
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok());
    ASSERT_TRUE((*capture)->write_event(event(StreamEventKind::disconnected, "gone")).ok());  // seq 1
    ASSERT_TRUE((*capture)->write(uls_averaging(1ms)).ok());                                  // seq 2
    ASSERT_TRUE((*capture)->write_event(event(StreamEventKind::reconnected, "back")).ok());   // seq 3
    ASSERT_TRUE((*capture)->write(ls5_result(24845, 49.69, ls5::SignalState::ok)).ok());      // seq 4
    ASSERT_TRUE((*capture)->write(uls_averaging(2ms)).ok());                                  // seq 5
  }
  const auto bound = capture_sample_bound(path);
  ASSERT_TRUE(bound.ok()) << bound.error().message;
  EXPECT_EQ(*bound, 4U);  // seq 2 to 5
  const auto empty = dir.file("empty.sqlite");
  ASSERT_TRUE(open_capture(empty).ok());
  const auto none = capture_sample_bound(empty);
  ASSERT_TRUE(none.ok()) << none.error().message;
  EXPECT_EQ(*none, 0U);
}

}  // namespace
}  // namespace rangekit::record
