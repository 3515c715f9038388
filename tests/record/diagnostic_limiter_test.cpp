// Bounded diagnostics (docs/reliability.md): "Repeated rejections are merged: the first of a
// kind is printed, then at most one summary line a second ("412 more bad frames in the last
// 1 s"). The counts stay exact in the events, the capture and the status line."
#include "rangekit/record/diagnostic_limiter.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>

#include "rangekit/record/capture.hpp"
#include "record/cli_process.hpp"
#include "record/fake_source.hpp"
#include "record/temp_dir.hpp"

namespace rangekit::record {
namespace {

using namespace std::chrono_literals;
using TimePoint = DiagnosticLimiter::TimePoint;

// Every count the summaries name ("N more bad frames ...") added up.
std::uint64_t merged_in(const std::string& text, std::size_t& summaries) {
  static const std::regex summary(R"((\d+) more bad frames in the last [0-9.e+-]+ s)");
  std::uint64_t total = 0;
  summaries = 0;
  for (std::sregex_iterator it(text.begin(), text.end(), summary), end; it != end; ++it) {
    total += std::strtoull((*it)[1].str().c_str(), nullptr, 10);
    ++summaries;
  }
  return total;
}

TEST(DiagnosticLimiter, FirstOfAKindPrintedThenOneSummaryASecond) {
  DiagnosticLimiter limiter;
  const TimePoint start{};
  auto lines = limiter.on_event(testing::event(StreamEventKind::bad_frame, "junk"), start);
  ASSERT_EQ(lines.size(), 1U);
  EXPECT_EQ(lines[0], "01:02:03.456 bad_frame: junk\n");
  // 412 more within the second: nothing printed.
  for (int i = 1; i <= 412; ++i) {
    EXPECT_TRUE(limiter.on_event(testing::event(StreamEventKind::bad_frame, "junk"), start + i * 2ms).empty());
  }
  // Another kind is not merged with bad frames.
  EXPECT_EQ(limiter.on_event(testing::event(StreamEventKind::disconnected, "gone"), start + 900ms).size(), 1U);
  lines = limiter.tick(start + 1s);
  ASSERT_EQ(lines.size(), 1U);
  EXPECT_EQ(lines[0], "412 more bad frames in the last 1 s\n");
  EXPECT_EQ(limiter.merged(), 412U);
  // A quiet second later the kind is new again: printed in full.
  EXPECT_TRUE(limiter.tick(start + 2s).empty());
  EXPECT_EQ(limiter.on_event(testing::event(StreamEventKind::bad_frame, "again"), start + 2500ms).size(), 1U);
  EXPECT_TRUE(limiter.finish(start + 2600ms).empty());
}

// Each sensor's connect and disconnect is said: with two sensors, "1 more connects" would
// hide which one came up.
TEST(DiagnosticLimiter, ALinksComingsAndGoingsAreEachSaid) {
  DiagnosticLimiter limiter;
  const TimePoint start{};
  EXPECT_EQ(limiter.on_event(testing::event(StreamEventKind::connected, "/dev/ttyUSB0: streaming"), start).size(), 1U);
  const auto second =
      limiter.on_event(testing::event(StreamEventKind::connected, "/dev/ttyUSB1: streaming"), start + 5ms);
  ASSERT_EQ(second.size(), 1U);
  EXPECT_NE(second[0].find("/dev/ttyUSB1: streaming"), std::string::npos) << second[0];
  EXPECT_EQ(limiter.on_event(testing::event(StreamEventKind::disconnected, "/dev/ttyUSB0: gone"), start + 9ms).size(),
            1U);
  EXPECT_TRUE(limiter.tick(start + 2s).empty());
  EXPECT_EQ(limiter.merged(), 0U);
}

TEST(DiagnosticLimiter, AMillionBadFramesInTenSecondsGiveAboutElevenLinesAndExactCounts) {
  DiagnosticLimiter limiter;
  const TimePoint start{};
  const std::uint64_t frames = 1'000'000;
  std::string printed;
  for (std::uint64_t i = 0; i < frames; ++i) {
    const auto now = start + std::chrono::microseconds(10 * i);  // 100,000 a second for 10 s
    for (const auto& line : limiter.on_event(testing::event(StreamEventKind::bad_frame, "junk"), now)) printed += line;
  }
  for (const auto& line : limiter.finish(start + 10s)) printed += line;
  std::size_t summaries = 0;
  const auto merged = merged_in(printed, summaries);
  EXPECT_EQ(merged + 1, frames) << printed;  // one printed in full, the rest counted
  EXPECT_LE(summaries, 11U) << printed;      // at most one a second, and the last at the end
  EXPECT_LT(printed.size(), 1000U) << printed;
}

// The CLI end: `rangekit replay` of a capture holding 200,000 bad frames (as a babbling line
// leaves them, each message a few hundred bytes: 80 MB of stderr before the change) prints
// under 100 KB on stderr, while its output keeps every event.
TEST(DiagnosticLimiter, ReplayOfABabbleCaptureKeepsStderrSmallAndEveryEventInTheOutput) {
  testing::TempDir dir;
  const auto path = dir.file("babble.sqlite");
  const std::uint64_t frames = 200'000;
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok());
    const std::string junk = "rejected 400 bytes: " + std::string(380, '?');
    for (std::uint64_t i = 0; i < frames; ++i) {
      ASSERT_TRUE((*capture)->write_event(testing::event(StreamEventKind::bad_frame, junk)).ok());
    }
    ASSERT_TRUE((*capture)->flush().ok());
  }
  const auto out = dir.file("out.jsonl");
  testing::CliProcess process({"replay", path, "--format", "jsonl", "--full-speed", "--out", out});
  // Replaying 200,000 events is CPU work: under ASan on a loaded machine it takes over 20 s.
  ASSERT_EQ(process.finish(std::chrono::minutes(2)), 0) << process.err().substr(0, 2000);
  EXPECT_LT(process.err().size(), 100U * 1024U);
  std::size_t summaries = 0;
  const auto merged = merged_in(process.err(), summaries);
  const auto printed_in_full = static_cast<std::uint64_t>(std::count(process.err().begin(), process.err().end(), '\n') -
                                                          static_cast<std::ptrdiff_t>(summaries));
  EXPECT_EQ(merged + printed_in_full, frames) << process.err().substr(0, 2000);
  std::ifstream file(out);
  std::uint64_t events = 0;
  for (std::string line; std::getline(file, line);) events += line.find("\"event\":\"bad_frame\"") != std::string::npos;
  EXPECT_EQ(events, frames);
}

}  // namespace
}  // namespace rangekit::record
