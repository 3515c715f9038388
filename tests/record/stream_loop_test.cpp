#include "rangekit/record/stream_loop.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "rangekit/ls5/family.hpp"
#include "rangekit/record/replay.hpp"
#include "record/fake_source.hpp"
#include "record/temp_dir.hpp"

namespace rangekit::record {
namespace {

using namespace testing;

std::size_t line_count(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

StreamLoopOptions to_file(const std::string& path, OutputFormat format = OutputFormat::jsonl) {
  StreamLoopOptions options;
  options.format = format;
  options.out = path;
  return options;
}

TEST(StreamLoop, SourceFinishedWritesEveryItemAsJsonLines) {
  TempDir dir;
  const auto path = dir.file("out.jsonl");
  FakeSource source({uls_error(), event(StreamEventKind::reconnected, "back"),
                     ls5_result(65535, std::nullopt, ls5::SignalState::lost)});
  const std::atomic<bool> stop{false};
  const auto outcome = run_stream_loop(source, to_file(path), stop);
  EXPECT_EQ(outcome.reason, StopReason::source_finished);
  EXPECT_EQ(outcome.stats.samples, 2u);
  EXPECT_EQ(outcome.stats.events, 1u);
  EXPECT_EQ(outcome.stats.errors, 1u);  // the ULS error sample
  EXPECT_EQ(read_file(path),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"uls\",\"address\":3,\"source\":\"/dev/ttyUSB0\","
            "\"kind\":\"error\",\"error\":4,\"error_text\":\"Lock Not Found (display: Target Not Found)\"}\n"
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"event\":\"reconnected\",\"message\":\"back\",\"count\":0}\n"
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"ls5\",\"address\":null,"
            "\"source\":\"udp:127.0.0.1:5000\",\"kind\":\"result\",\"code\":65535,\"distance_mm\":null,"
            "\"signal\":\"lost\"}\n");
}

// Several sensors in one stream (capture): each one's samples are counted apart, so one that
// sends nothing is not summed away.
TEST(StreamLoop, CountsEachSourcesSamplesApart) {
  TempDir dir;
  auto second = uls_error();
  second.source = "/dev/ttyUSB1";
  FakeSource source(
      {uls_error(), ls5_result(65535, std::nullopt, ls5::SignalState::lost), uls_error(), second, uls_error()});
  const std::atomic<bool> stop{false};
  const auto outcome = run_stream_loop(source, to_file(dir.file("out.jsonl")), stop);
  ASSERT_EQ(outcome.stats.sources.size(), 3U);
  EXPECT_EQ(outcome.stats.sources[0].name, "uls /dev/ttyUSB0");
  EXPECT_EQ(outcome.stats.sources[0].samples, 3U);
  EXPECT_EQ(outcome.stats.sources[1].name, "ls5 udp:127.0.0.1:5000");
  EXPECT_EQ(outcome.stats.sources[1].samples, 1U);
  EXPECT_EQ(outcome.stats.sources[2].name, "uls /dev/ttyUSB1");
  EXPECT_EQ(outcome.stats.sources[2].samples, 1U);
}

TEST(StreamLoop, StopsAfterCountSamplesAndStopsTheSource) {
  TempDir dir;
  const auto path = dir.file("out.csv");
  std::vector<StreamItem> items;
  for (int i = 0; i < 10; ++i) items.emplace_back(uls_averaging(std::chrono::milliseconds(i)));
  FakeSource source(items, true);
  auto options = to_file(path, OutputFormat::csv);
  options.count = 3;
  const std::atomic<bool> stop{false};
  const auto outcome = run_stream_loop(source, options, stop);
  EXPECT_EQ(outcome.reason, StopReason::count_reached);
  EXPECT_EQ(outcome.stats.samples, 3u);
  EXPECT_TRUE(source.stopped());
  EXPECT_EQ(line_count(read_file(path)), 4u);  // header + 3 rows
}

// A live stream's queue hands over everything queued at once: this one
// has all its items in one batch and refuses single next() calls.
class OneBatchSource final : public SampleSource {
 public:
  explicit OneBatchSource(std::vector<StreamItem> items) : items_(std::move(items)) {}
  std::optional<StreamItem> next(std::chrono::milliseconds /*timeout*/) override {
    ADD_FAILURE() << "the loop took an item one by one";
    return std::nullopt;
  }
  bool next_batch(std::vector<StreamItem>& batch, std::chrono::milliseconds /*timeout*/) override {
    ++batches_taken;
    batch.clear();
    if (items_.empty()) return false;
    batch.swap(items_);
    return true;
  }
  [[nodiscard]] bool finished() const override { return items_.empty(); }
  void stop() override { stopped = true; }
  int batches_taken = 0;
  bool stopped = false;

 private:
  std::vector<StreamItem> items_;
};

TEST(StreamLoop, TakesABatchAtOnceAndWritesItInOrder) {
  TempDir dir;
  const auto path = dir.file("out.jsonl");
  OneBatchSource source({uls_averaging(0ms), event(StreamEventKind::lost_records, "gap", 2), uls_averaging(1ms)});
  const std::atomic<bool> stop{false};
  const auto outcome = run_stream_loop(source, to_file(path), stop);
  EXPECT_EQ(outcome.reason, StopReason::source_finished);
  EXPECT_EQ(source.batches_taken, 2);  // the batch, then the empty answer of a finished source
  EXPECT_EQ(outcome.stats.samples, 2u);
  EXPECT_EQ(outcome.stats.lost, 2u);
  const std::string text = read_file(path);
  EXPECT_EQ(line_count(text), 3u);
  const auto first = text.find("\"time\":\"2026-11-26T01:02:03.456Z\",\"device\"");
  const auto gap = text.find("\"event\":\"lost_records\"");
  const auto second = text.find("\"time\":\"2026-11-26T01:02:03.457Z\",\"device\"");
  ASSERT_NE(first, std::string::npos);
  ASSERT_NE(gap, std::string::npos);
  ASSERT_NE(second, std::string::npos);
  EXPECT_LT(first, gap);
  EXPECT_LT(gap, second);
}

TEST(StreamLoop, ACountReachedInsideABatchWritesNoMore) {
  TempDir dir;
  const auto path = dir.file("out.csv");
  std::vector<StreamItem> items;
  for (int i = 0; i < 10; ++i) items.emplace_back(uls_averaging(std::chrono::milliseconds(i)));
  OneBatchSource source(std::move(items));
  auto options = to_file(path, OutputFormat::csv);
  options.count = 3;
  const std::atomic<bool> stop{false};
  const auto outcome = run_stream_loop(source, options, stop);
  EXPECT_EQ(outcome.reason, StopReason::count_reached);
  EXPECT_EQ(outcome.stats.samples, 3u);
  EXPECT_TRUE(source.stopped);
  EXPECT_EQ(line_count(read_file(path)), 4u);  // header + 3 rows
}

TEST(StreamLoop, StopsAfterDurationOnAQuietSource) {
  FakeSource source({}, true);
  StreamLoopOptions options;
  options.write_output = false;
  options.duration_s = 0.3;
  const std::atomic<bool> stop{false};
  const auto started = std::chrono::steady_clock::now();
  const auto outcome = run_stream_loop(source, options, stop);
  const auto took = std::chrono::steady_clock::now() - started;
  EXPECT_EQ(outcome.reason, StopReason::duration_reached);
  EXPECT_GE(took, 300ms);
  EXPECT_LT(took, 10s);
  EXPECT_TRUE(source.stopped());
}

TEST(StreamLoop, StopRequestEndsTheRunAsInterrupted) {
  TempDir dir;
  FakeSource source({uls_averaging(), event(StreamEventKind::disconnected, "cable"), uls_averaging()}, true);
  std::atomic<bool> stop{false};
  StreamObserver observer;
  observer.on_event = [&stop](const StreamEvent&) { stop = true; };  // as if Ctrl-C came with the event
  const auto outcome = run_stream_loop(source, to_file(dir.file("out.jsonl")), stop, observer);
  EXPECT_EQ(outcome.reason, StopReason::interrupted);
  EXPECT_EQ(outcome.stats.samples, 1u);
  EXPECT_EQ(outcome.stats.disconnects, 1u);
  EXPECT_TRUE(outcome.stats.link_down);
  EXPECT_TRUE(source.stopped());
  EXPECT_EQ(line_count(read_file(dir.file("out.jsonl"))), 2u);  // the sample and the event, flushed on close
}

TEST(StreamLoop, WriteFailureNamesTheFileAndKeepsTheCapture) {
  TempDir dir;
  const auto capture = dir.file("kept.sqlite");
  std::vector<StreamItem> items;
  for (int i = 0; i < 5; ++i) items.emplace_back(uls_averaging(std::chrono::milliseconds(i)));
  FakeSource source(items);
  auto options = to_file("/dev/full");
  options.capture = capture;
  const std::atomic<bool> stop{false};
  const auto outcome = run_stream_loop(source, options, stop);
  EXPECT_EQ(outcome.reason, StopReason::write_failed);
  ASSERT_TRUE(outcome.error.has_value());
  EXPECT_NE(outcome.error->message.find("/dev/full"), std::string::npos) << outcome.error->message;
  auto replay = open_replay(capture, 0.0);
  ASSERT_TRUE(replay.ok());
  int replayed = 0;
  while ((*replay)->next(1000ms)) ++replayed;
  EXPECT_EQ(replayed, 5);
}

TEST(StreamLoop, UnopenableOutputFailsBeforeReading) {
  FakeSource source({uls_averaging()});
  const std::atomic<bool> stop{false};
  const auto outcome = run_stream_loop(source, to_file("/nonexistent-dir/out.jsonl"), stop);
  EXPECT_EQ(outcome.reason, StopReason::open_failed);
  EXPECT_EQ(outcome.stats.samples, 0u);
}

TEST(StreamLoop, StatusReportsComeWhileStreaming) {
  FakeSource source({event(StreamEventKind::lost_records, "gap", 7)}, true);
  StreamLoopOptions options;
  options.write_output = false;
  options.duration_s = 0.5;
  StreamObserver observer;
  observer.status_interval = 100ms;
  std::vector<StreamStats> reports;
  observer.on_status = [&reports](const StreamStats& stats) { reports.push_back(stats); };
  const std::atomic<bool> stop{false};
  const auto outcome = run_stream_loop(source, options, stop, observer);
  ASSERT_FALSE(reports.empty());
  EXPECT_EQ(reports.back().lost, 7u);
  EXPECT_EQ(outcome.stats.lost, 7u);
}

}  // namespace
}  // namespace rangekit::record
