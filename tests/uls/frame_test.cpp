// scan_frame and the FrameAssembler on ULS byte streams (F1-F5, U4, U25).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rangekit/uls/uls.hpp"

namespace rangekit::uls {
namespace {

FrameScan scan(std::string_view text) { return scan_frame(as_bytes(text)); }

TEST(UlsFramer, FindsPlainAndAddressedFrames) {
  const FrameScan plain = scan("$MM,1\r$OK\r");
  ASSERT_EQ(plain.status, FrameStatus::complete);
  EXPECT_EQ(as_text(plain.frame), "$MM,1");
  EXPECT_EQ(plain.consumed, 6U);
  const FrameScan addressed = scan("#ZMM,1\r");
  ASSERT_EQ(addressed.status, FrameStatus::complete);
  EXPECT_EQ(as_text(addressed.frame), "#ZMM,1");
}

TEST(UlsFramer, AddressSlotTakesAnyByteButOnlyInHashFrames) {  // F4, U4
  const FrameScan high = scan("#\xA0US\r");
  ASSERT_EQ(high.status, FrameStatus::complete);
  EXPECT_EQ(high.frame.size(), 4U);
  // Same byte at offset 1 of a '$' frame: not an address slot.
  const FrameScan plain = scan("$\xA0US\r");
  EXPECT_EQ(plain.status, FrameStatus::invalid);
  EXPECT_STREQ(plain.reason, "control or non-ASCII byte inside a frame");
  // A start byte in the address slot is taken as the address and refused by the parser.
  const FrameScan dollar_address = scan("#$US\r");
  ASSERT_EQ(dollar_address.status, FrameStatus::complete);
  const Result<FrameView> parsed = parse_frame(dollar_address.frame);
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.error().message, "ULS frame: address byte 0x24 below 0x30");
}

TEST(UlsFramer, WaitsForTheCr) {
  EXPECT_EQ(scan("$MM,1").status, FrameStatus::need_more);
  EXPECT_EQ(scan("#").status, FrameStatus::need_more);
  EXPECT_EQ(scan("$UA,\xEF").status, FrameStatus::need_more);  // U25 shape, not yet complete
  EXPECT_EQ(scan("").status, FrameStatus::need_more);
}

TEST(UlsFramer, UnitAddressValueSlotOnlyInThatShape) {  // U25
  const FrameScan set = scan("$ua,\xC0\r");
  ASSERT_EQ(set.status, FrameStatus::complete);
  EXPECT_EQ(set.consumed, 6U);
  EXPECT_EQ(scan("#ZUA,\xC0\r").status, FrameStatus::complete);
  EXPECT_EQ(scan("$UA,\xC0X\r").status, FrameStatus::invalid);
  EXPECT_EQ(scan("$UB,\xC0\r").status, FrameStatus::invalid);
  EXPECT_EQ(scan("$UA;\xC0\r").status, FrameStatus::invalid);
  // "#<CR>": the CR ends an empty addressed frame, whatever follows.
  const FrameScan cut = scan("#\rUA,\xC0\r");
  ASSERT_EQ(cut.status, FrameStatus::complete);
  EXPECT_EQ(cut.consumed, 2U);
}

TEST(UlsFramer, LongestFrameIs64Bytes) {  // F5
  const std::string longest = "$ID," + std::string(60, 'v');
  ASSERT_EQ(longest.size(), 64U);
  EXPECT_EQ(scan(longest + "\r").status, FrameStatus::complete);
  EXPECT_TRUE(parse_frame(std::string_view(longest)).ok());
  const FrameScan too_long = scan(longest + "v\r");
  EXPECT_EQ(too_long.status, FrameStatus::invalid);
  EXPECT_STREQ(too_long.reason, "frame longer than the protocol allows");
}

struct Collected {
  std::vector<std::string> frames;
  std::vector<std::string> rejected;
};

Collected collect(std::string_view stream, std::size_t chunk) {
  FrameAssembler assembler(scan_frame, 256);
  Collected out;
  for (std::size_t at = 0; at < stream.size(); at += chunk) {
    assembler.push(as_bytes(stream.substr(at, chunk)));
    FrameAssembler::Event event;
    while (assembler.next(event)) {
      if (event.kind == FrameAssembler::Event::Kind::frame) {
        out.frames.emplace_back(as_text(event.frame));
      } else {
        out.rejected.emplace_back(event.reason);
      }
    }
  }
  return out;
}

TEST(UlsFramer, AssemblerSplitsAStreamIntoFrames) {
  const std::string_view stream = "\r\n$BM,12.345\r#Z0BB8\rjunk$ER,4\r$MM,\n$OK\r";
  const std::vector<std::string> frames{"$BM,12.345", "#Z0BB8", "$ER,4", "$OK"};
  const Collected whole = collect(stream, stream.size());
  EXPECT_EQ(whole.frames, frames);
  EXPECT_EQ(whole.rejected, (std::vector<std::string>{"bytes before the start of a frame",
                                                      "line feed inside a frame (frames end with CR)"}));
  // One byte at a time, as a serial port may deliver it: same frames; the junk
  // is rejected byte by byte because each byte is all the framer has seen.
  const Collected trickle = collect(stream, 1);
  EXPECT_EQ(trickle.frames, frames);
  EXPECT_EQ(trickle.rejected.size(), 5U);
}

TEST(UlsFramer, ParseWireFrameWantsExactlyOneFrame) {
  EXPECT_TRUE(parse_wire_frame(as_bytes("$MM,1\r")).ok());
  const auto error_of = [](std::string_view wire) {
    const Result<FrameView> parsed = parse_wire_frame(as_bytes(wire));
    EXPECT_FALSE(parsed.ok()) << wire;
    return parsed.ok() ? Error{Errc::io, "", 0} : parsed.error();
  };
  EXPECT_EQ(error_of("$MM,1").code, Errc::truncated);
  EXPECT_EQ(error_of("$MM,1\r$OK\r").message, "ULS frame: 4 bytes after the CR");
  EXPECT_EQ(error_of("\r$MM\r").message, "ULS frame: line ending before the start byte");
  EXPECT_EQ(error_of("").message, "ULS frame: no bytes");
}

}  // namespace
}  // namespace rangekit::uls
