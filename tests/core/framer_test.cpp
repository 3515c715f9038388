// The shared line framer and frame assembler (docs/conformance.md F1-F5).
#include <gtest/gtest.h>

#include <string>

#include "rangekit/core/framer.hpp"

namespace rangekit {
namespace {

const LineFramerRules uls_like{"$#", '\r', 64, true, 1};

FrameScan scan(std::string_view text) { return scan_line_frame(as_bytes(text), uls_like); }

TEST(LineFramer, CompleteFrameExcludesTerminator) {
  const auto result = scan("$MM,1\r$OK\r");
  ASSERT_EQ(result.status, FrameStatus::complete);
  EXPECT_EQ(as_text(result.frame), "$MM,1");
  EXPECT_EQ(result.consumed, 6U);
}

TEST(LineFramer, NeedsMoreWithoutTerminator) {
  EXPECT_EQ(scan("$MM,1").status, FrameStatus::need_more);
  EXPECT_EQ(scan("").status, FrameStatus::need_more);
}

TEST(LineFramer, LineEndingsBetweenFramesAreBenign) {  // F1
  const auto result = scan("\r\n\n$OK\r");
  ASSERT_EQ(result.status, FrameStatus::invalid);
  EXPECT_TRUE(result.benign());
  EXPECT_EQ(result.consumed, 3U);
}

TEST(LineFramer, GarbageBeforeStartIsRejectedUpToNextStart) {  // F2
  const auto result = scan("xyz$OK\r");
  ASSERT_EQ(result.status, FrameStatus::invalid);
  EXPECT_FALSE(result.benign());
  EXPECT_EQ(result.consumed, 3U);
  EXPECT_STREQ(result.reason, "bytes before the start of a frame");
}

TEST(LineFramer, NewStartInsideFrameCutsItShort) {  // F3
  const auto result = scan("$BM,1.2$BM,1.3\r");
  ASSERT_EQ(result.status, FrameStatus::invalid);
  EXPECT_EQ(result.consumed, 7U);
  EXPECT_STREQ(result.reason, "frame cut short by a new start byte");
}

TEST(LineFramer, LineFeedInsideFrameIsWrongTerminator) {  // F1
  const auto result = scan("$MM,1\n");
  ASSERT_EQ(result.status, FrameStatus::invalid);
  EXPECT_EQ(result.consumed, 6U);
  EXPECT_STREQ(result.reason, "line feed inside a frame (frames end with CR)");
}

TEST(LineFramer, EmbeddedNulIsInvalid) {  // F4
  const std::string text("$M\0M\r", 5);
  const auto result = scan(text);
  ASSERT_EQ(result.status, FrameStatus::invalid);
  EXPECT_EQ(result.consumed, 3U);
}

TEST(LineFramer, HighByteAllowedOnlyInAddressSlot) {  // F4
  const std::string addressed("#\xC8MM\r");
  EXPECT_EQ(scan(addressed).status, FrameStatus::complete);
  const std::string elsewhere("#Z\xC8M\r");
  EXPECT_EQ(scan(elsewhere).status, FrameStatus::invalid);
}

TEST(LineFramer, OverlongFrameIsRejected) {  // F5
  const std::string longest = "$" + std::string(63, 'A') + "\r";
  EXPECT_EQ(scan(longest).status, FrameStatus::complete);
  const std::string too_long = "$" + std::string(64, 'A') + "\r";
  const auto result = scan(too_long);
  ASSERT_EQ(result.status, FrameStatus::invalid);
  EXPECT_STREQ(result.reason, "frame longer than the protocol allows");
  // Without a terminator in sight, the framer gives up once the limit is passed.
  EXPECT_EQ(scan("$" + std::string(80, 'A')).status, FrameStatus::invalid);
}

FrameScan scan_uls_like(Bytes bytes) noexcept { return scan_line_frame(bytes, uls_like); }

TEST(FrameAssembler, SplitsFramesFedByteByByte) {
  FrameAssembler assembler(&scan_uls_like, 128);
  const std::string stream = "junk$MM,1\r\n$OK\r$ER,4\r";
  std::vector<std::string> frames;
  std::vector<std::string> rejections;
  FrameAssembler::Event event;
  for (const char c : stream) {
    const auto byte = static_cast<std::uint8_t>(c);
    ASSERT_EQ(assembler.push(Bytes(&byte, 1)), 1U);
    while (assembler.next(event)) {
      if (event.kind == FrameAssembler::Event::Kind::frame)
        frames.emplace_back(as_text(event.frame));
      else
        rejections.emplace_back(event.reason);
    }
  }
  EXPECT_EQ(frames, (std::vector<std::string>{"$MM,1", "$OK", "$ER,4"}));
  // Fed one byte at a time, each garbage byte is its own rejection.
  EXPECT_EQ(rejections, std::vector<std::string>(4, "bytes before the start of a frame"));
}

TEST(FrameAssembler, FullBufferWithoutFrameEndIsRejectedNotStuck) {
  // A framer that tolerates longer frames than the assembler can hold.
  FrameAssembler assembler(
      [](Bytes bytes) noexcept {
        return scan_line_frame(bytes, LineFramerRules{"$", '\r', 1000, false, 0});
      },
      16);
  const std::string stream = "$" + std::string(40, 'A');
  std::size_t offset = 0;
  int rejected = 0;
  FrameAssembler::Event event;
  while (offset < stream.size()) {
    offset += assembler.push(as_bytes(std::string_view(stream).substr(offset)));
    while (assembler.next(event)) {
      if (event.kind == FrameAssembler::Event::Kind::rejected) ++rejected;
    }
  }
  EXPECT_GE(rejected, 1);
  EXPECT_LT(assembler.buffered(), 16U);
}

// A read as large as the assembler on top of a half frame it holds: push() takes what fits
// and feed_all hands the rest over once frames have made room, so no byte is lost (the LS5
// stream reader dropped them: a 4 KiB read into a 4 KiB assembler holding part of a record).
TEST(FrameAssembler, FeedAllLosesNothingWhenAReadOverfillsTheBuffer) {
  FrameAssembler assembler(&scan_uls_like, 16);
  std::vector<std::string> frames;
  FrameAssembler::Event event;
  const auto drain = [&] {
    while (assembler.next(event)) {
      if (event.kind == FrameAssembler::Event::Kind::frame) frames.emplace_back(as_text(event.frame));
    }
  };
  feed_all(assembler, as_bytes(std::string_view("$AB")), drain);
  const std::string read = "C\r$DEF\r$GHI\r$JK\r";  // 16 bytes: 3 of them do not fit at first
  ASSERT_EQ(read.size(), 16U);
  EXPECT_LT(assembler.push(as_bytes(std::string_view(read))), read.size()) << "the case this test is about";
  assembler.clear();
  frames.clear();
  feed_all(assembler, as_bytes(std::string_view("$AB")), drain);
  feed_all(assembler, as_bytes(std::string_view(read)), drain);
  EXPECT_EQ(frames, (std::vector<std::string>{"$ABC", "$DEF", "$GHI", "$JK"}));
  EXPECT_EQ(assembler.buffered(), 0U);
}

}  // namespace
}  // namespace rangekit
