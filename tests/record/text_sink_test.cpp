#include <gtest/gtest.h>

#include "rangekit/record/text_sink.hpp"
#include "record/fake_source.hpp"
#include "record/temp_dir.hpp"

namespace rangekit::record {
namespace {

using namespace testing;

TEST(TextSink, JsonlFileHoldsOneLinePerItem) {
  TempDir dir;
  const auto path = dir.file("out.jsonl");
  {
    auto sink = open_text_sink(OutputFormat::jsonl, path);
    ASSERT_TRUE(sink.ok()) << sink.error().message;
    ASSERT_TRUE((*sink)->write(uls_error()).ok());
    ASSERT_TRUE((*sink)->write_event(event(StreamEventKind::reconnected, "back")).ok());
    ASSERT_TRUE((*sink)->flush().ok());
  }
  EXPECT_EQ(read_file(path),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"uls\",\"address\":3,\"source\":\"/dev/ttyUSB0\","
            "\"kind\":\"error\",\"error\":4,\"error_text\":\"Lock Not Found (display: Target Not Found)\"}\n"
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"event\":\"reconnected\",\"message\":\"back\",\"count\":0}\n");
}

TEST(TextSink, CsvStartsWithTheHeaderAndLeavesEventsOut) {
  TempDir dir;
  const auto path = dir.file("out.csv");
  {
    auto sink = open_text_sink(OutputFormat::csv, path);
    ASSERT_TRUE(sink.ok());
    ASSERT_TRUE((*sink)->write_event(event(StreamEventKind::disconnected, "gone")).ok());
    ASSERT_TRUE((*sink)->write(uls_error()).ok());
  }  // closing flushes
  EXPECT_EQ(read_file(path),
            "time,device,address,source,kind,distance_m,pulse_width_ns,targets,presence,pulses_between_events,pulses_"
            "overflow,error,"
            "code,distance_mm,signal,derivative_mm,error_text,suspect,suspect_reason\n"
            "2026-11-26T01:02:03.456Z,uls,3,/dev/ttyUSB0,error,,,,,,,4,,,,,Lock Not Found (display: Target Not "
            "Found),false,\n");
}

TEST(TextSink, DiskFullIsAnIoErrorNamingTheFile) {
  auto sink = open_text_sink(OutputFormat::jsonl, "/dev/full");
  ASSERT_TRUE(sink.ok()) << sink.error().message;
  ASSERT_TRUE((*sink)->write(uls_averaging()).ok());  // buffered
  const auto flushed = (*sink)->flush();
  ASSERT_FALSE(flushed.ok());
  EXPECT_EQ(flushed.error().code, Errc::io);
  EXPECT_NE(flushed.error().message.find("/dev/full"), std::string::npos) << flushed.error().message;
  EXPECT_NE(flushed.error().message.find("No space left on device"), std::string::npos) << flushed.error().message;
  EXPECT_FALSE((*sink)->write(uls_averaging()).ok());  // stays failed
}

TEST(TextSink, UnopenableFileIsAnIoError) {
  const auto sink = open_text_sink(OutputFormat::text, "/nonexistent-dir/out.txt");
  ASSERT_FALSE(sink.ok());
  EXPECT_EQ(sink.error().code, Errc::io);
  EXPECT_NE(sink.error().message.find("/nonexistent-dir/out.txt"), std::string::npos);
}

TEST(OutputFormat, ParsesTheThreeNames) {
  EXPECT_EQ(*parse_output_format("jsonl"), OutputFormat::jsonl);
  EXPECT_EQ(*parse_output_format("csv"), OutputFormat::csv);
  EXPECT_EQ(*parse_output_format("text"), OutputFormat::text);
  EXPECT_FALSE(parse_output_format("json").ok());
}

}  // namespace
}  // namespace rangekit::record
