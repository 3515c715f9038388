// Malformed input: every bad line gives an Error naming the problem; nothing
// throws or crashes (F4, U4, U25, U28). Random buffers use a fixed seed.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "rangekit/uls/uls.hpp"

namespace rangekit::uls {
namespace {

struct Case {
  std::string_view wire;  // bytes as received, CR included where present
  Errc code;
  std::string_view names;  // the message must contain this
};

// Framing and syntax, through parse_wire_frame (framer + parser).
const Case frame_cases[] = {
    {"$MM,1", Errc::truncated, "no CR terminator"},
    {"#", Errc::truncated, "no CR terminator"},
    {"#\r", Errc::truncated, "'#' frame without an address byte"},
    {"$\r", Errc::truncated, "empty mnemonic"},
    {"#Z\r", Errc::truncated, "empty mnemonic"},
    {"$,1\r", Errc::truncated, "empty mnemonic"},
    {"$MM,1\n", Errc::invalid_frame, "line feed inside a frame"},
    {"$MM,1\n\r", Errc::invalid_frame, "line feed inside a frame"},
    {std::string_view("$MM,\0"
                      "1\r",
                      7),
     Errc::invalid_frame, "control or non-ASCII byte"},
    {"$MM,\x7F\r", Errc::invalid_frame, "control or non-ASCII byte"},
    {"$MM,\xC0\r", Errc::invalid_frame, "control or non-ASCII byte"},
    {"#/MM,1\r", Errc::invalid_frame, "address byte 0x2F below 0x30"},
    {"#\x01MM,1\r", Errc::invalid_frame, "address byte 0x01 below 0x30"},
    {"#,MM\r", Errc::invalid_frame, "address byte 0x2C below 0x30"},
    {"$M\r", Errc::invalid_frame, "is not 2 to 4 letters"},
    {"$MMMMM,1\r", Errc::invalid_frame, "'MMMMM' is not 2 to 4 letters"},
    {"$M1,1\r", Errc::invalid_frame, "'M1' holds a non-letter"},
    {"$M M\r", Errc::invalid_frame, "holds a non-letter"},
    {"$MM,\r", Errc::invalid_frame, "field 1 is empty"},
    {"$BR,,9600\r", Errc::invalid_frame, "field 1 is empty"},
    {"$PF,1,2,\r", Errc::invalid_frame, "field 3 is empty"},
    {"$BM,1,2,3,4,5,6,7,8,9\r", Errc::overlong, "more than 8 fields"},
    {"$0BG8\r", Errc::bad_hex, "'0BG8' is not '0' or 4 upper-case hex digits"},
    {"$0bb8\r", Errc::bad_hex, "upper-case hex"},
    {"$00\r", Errc::bad_hex, "time between events '00'"},
    {"#Z12345\r", Errc::bad_hex, "time between events '12345'"},
    {"$MM,1\r$OK\r", Errc::invalid_frame, "bytes after the CR"},
    {"xx$MM\r", Errc::invalid_frame, "bytes before the start of a frame"},
    {"$BM,1.2$BM,1.3\r", Errc::invalid_frame, "cut short by a new start byte"},
};

TEST(UlsMalformed, FramesAreRefusedWithTheirReason) {
  for (const Case& bad : frame_cases) {
    SCOPED_TRACE(std::string(bad.wire));
    const Result<FrameView> parsed = parse_wire_frame(as_bytes(bad.wire));
    ASSERT_FALSE(parsed.ok());
    EXPECT_EQ(parsed.error().code, bad.code) << parsed.error().describe();
    EXPECT_NE(parsed.error().message.find(bad.names), std::string::npos) << parsed.error().message;
    EXPECT_EQ(parsed.error().message.rfind("ULS frame: ", 0), 0U);
  }
}

TEST(UlsMalformed, Overlong) {
  const std::string frame = "$ID," + std::string(61, 'v');  // 65 bytes before the CR
  const Result<FrameView> wire = parse_wire_frame(as_bytes(frame + "\r"));
  ASSERT_FALSE(wire.ok());
  EXPECT_EQ(wire.error().code, Errc::overlong);
  const Result<FrameView> direct = parse_frame(std::string_view(frame));
  ASSERT_FALSE(direct.ok());
  EXPECT_EQ(direct.error().message, "ULS frame: 65 bytes, longer than 64");
  const std::array<std::string_view, 1> long_field{std::string_view(frame).substr(4)};
  const Result<FrameText> encoded = encode_value_reply(Address::none(), "ID", long_field);
  ASSERT_FALSE(encoded.ok());
  EXPECT_EQ(encoded.error().code, Errc::overlong);
}

TEST(UlsMalformed, ParseFrameSeesWhatTheFramerWouldRefuse) {  // F4 inside parse_frame too
  const auto message = [](std::string_view frame) {
    const Result<FrameView> parsed = parse_frame(frame);
    EXPECT_FALSE(parsed.ok()) << frame;
    return parsed.ok() ? std::string() : parsed.error().message;
  };
  EXPECT_EQ(message(std::string_view("$MM,\0"
                                     "1",
                                     6)),
            "ULS frame: embedded NUL at offset 4");
  EXPECT_EQ(message("$MM,1\n"), "ULS frame: line feed at offset 5 (frames end with CR)");
  EXPECT_EQ(message("$MM,1\r"), "ULS frame: CR inside the frame at offset 5");
  EXPECT_EQ(message("$MM,\x1B"), "ULS frame: control byte 0x1B at offset 4");
  EXPECT_EQ(message("$MM,\xC3"), "ULS frame: non-ASCII byte 0xC3 at offset 4");
  EXPECT_EQ(message("#ZMM,$"), "ULS frame: start byte '$' at offset 5");
  EXPECT_EQ(message(""), "ULS frame: empty");
  EXPECT_EQ(message("MM,1"), "ULS frame: starts with 0x4D, not '$' or '#'");
}

struct DecodeCase {
  std::string_view frame;  // without CR
  Errc code;
  std::string_view names;
};

TEST(UlsMalformed, RepliesWithBadValues) {
  const DecodeCase cases[] = {
      {"$AW,abc", Errc::bad_number, "AW value 'abc' is not an integer"},
      {"$AW,0", Errc::out_of_range, "AW value '0' is out of range"},
      {"$LG,far", Errc::bad_number, "LG value 'far' is not a number"},
      {"$TT,10G", Errc::bad_hex, "TT value '10G' is not 1-8 hex digits"},
      {"$TT,123456789", Errc::bad_hex, "is not 1-8 hex digits"},
      {"$ER,x", Errc::bad_number, "error number 'x'"},
      {"$ER,4,5", Errc::overlong, "ER needs one error number"},
      {"$MM", Errc::truncated, "MM reply has 0 values, expected 1"},
      {"$PF,1000,1000", Errc::truncated, "PF reply has 2 values, expected 3"},
      {"$ID,1,2,3,4,5,6,7,8", Errc::invalid_frame, ""},  // 8 fields fit
      {"$0BB8", Errc::wrong_form, "time-between-events frame is not a reply"},
      {"$QQ,1", Errc::unknown_command, "'QQ' is not a ULS command"},
  };
  for (const DecodeCase& bad : cases) {
    SCOPED_TRACE(std::string(bad.frame));
    const Result<Reply> reply = decode_reply(as_bytes(bad.frame));
    if (bad.names.empty()) {
      EXPECT_TRUE(reply.ok());
      continue;
    }
    ASSERT_FALSE(reply.ok());
    EXPECT_EQ(reply.error().code, bad.code) << reply.error().describe();
    EXPECT_NE(reply.error().message.find(bad.names), std::string::npos) << reply.error().message;
  }
}

TEST(UlsMalformed, MeasurementLinesWithBadFields) {
  const MeasurementContext both{Mode::averaging, DisplayMode::range_and_intensity, Units::metres, false};
  const MeasurementContext binning{Mode::binning, DisplayMode::range, Units::metres, false};
  const DecodeCase averaging_cases[] = {
      {"$BM,1.234", Errc::truncated, "has 1 fields, needs 2"},
      {"$BM,1.234,5,6", Errc::overlong, "has 3 fields, needs 2"},
      {"$BM,abc.def,5", Errc::bad_number, "range 'abc.def' is not a number"},
      {"$BM,1.2.3,5", Errc::bad_number, "is not a number"},
      {"$BM,.123,5", Errc::bad_number, "is not a number"},
      {"$BM,12345.678,5", Errc::overlong, "longer than 8 characters"},
      {"$BM,1.234,x", Errc::bad_number, "pulse width 'x' is not a number"},
      {"$BM,1.234,12345678", Errc::overlong, "pulse width '12345678' is above 9999999"},
      {"$BM,1.234,-5", Errc::bad_number, "pulse width '-5'"},
      {"$ER,0", Errc::out_of_range, "error number 0 is not an error"},
      {"$OK", Errc::wrong_form, "'OK' is not BM or ER"},
  };
  for (const DecodeCase& bad : averaging_cases) {
    SCOPED_TRACE(std::string(bad.frame));
    const Result<Measurement> decoded = decode_measurement(as_bytes(bad.frame), both);
    ASSERT_FALSE(decoded.ok());
    EXPECT_EQ(decoded.error().code, bad.code) << decoded.error().describe();
    EXPECT_NE(decoded.error().message.find(bad.names), std::string::npos) << decoded.error().message;
  }
  const DecodeCase binning_cases[] = {
      {"$BM,0,2,1.000", Errc::truncated, "binning line has 3 fields, needs 4"},
      {"$BM,a,2,1.000,5", Errc::bad_number, "target index 'a'"},
      {"$BM,15,16,1.000,5", Errc::out_of_range, "target index '15' is above 14"},
      {"$BM,0,0,1.000,5", Errc::out_of_range, "is not below count 0"},
      {"$BM,0,1,1.000,65536", Errc::out_of_range, "strength '65536' is above 65535"},
  };
  for (const DecodeCase& bad : binning_cases) {
    SCOPED_TRACE(std::string(bad.frame));
    const Result<Measurement> decoded = decode_measurement(as_bytes(bad.frame), binning);
    ASSERT_FALSE(decoded.ok());
    EXPECT_EQ(decoded.error().code, bad.code) << decoded.error().describe();
    EXPECT_NE(decoded.error().message.find(bad.names), std::string::npos) << decoded.error().message;
  }
}

TEST(UlsMalformed, EncodersRefuseWhatCannotBeParsed) {
  EXPECT_EQ(encode_get(Address::none(), "M").error().code, Errc::invalid_frame);
  EXPECT_EQ(encode_get(Address::none(), "M1").error().code, Errc::invalid_frame);
  const std::array<std::string_view, 1> comma{"1,2"};
  const std::array<std::string_view, 1> empty{""};
  const std::array<std::string_view, 1> start{"$"};
  const std::array<std::string_view, 1> control{"\x07"};
  EXPECT_NE(encode_set(Address::none(), "MM", comma).error().message.find("holds byte 0x2C"), std::string::npos);
  EXPECT_NE(encode_set(Address::none(), "MM", empty).error().message.find("field 1 is empty"), std::string::npos);
  EXPECT_FALSE(encode_set(Address::none(), "MM", start).ok());
  EXPECT_FALSE(encode_set(Address::none(), "MM", control).ok());
  EXPECT_FALSE(encode_set(Address::none(), "MM", std::span<const std::string_view>{}).ok());
  const std::array<std::string_view, 9> nine{"1", "2", "3", "4", "5", "6", "7", "8", "9"};
  EXPECT_EQ(encode_value_reply(Address::none(), "BM", nine).error().code, Errc::overlong);
  EXPECT_FALSE(encode_error_reply(Address::none(), -1).ok());
  EXPECT_FALSE(encode_error_reply(Address::none(), 1000).ok());
}

// Random buffers through framer and parser: no throw, no crash, and every
// refusal comes with a reason.
TEST(UlsMalformed, RandomBuffersThroughFramerAndParser) {
  std::mt19937 random(20050301);  // fixed seed: "First Edition: March 2005"
  std::uniform_int_distribution<int> length(0, 80);
  std::uniform_int_distribution<int> byte(0, 255);
  const std::string_view alphabet = "$#,.0123456789ABCDEFMBOKERZ\r\n";  // bytes that reach deeper paths
  std::uniform_int_distribution<std::size_t> pick(0, alphabet.size() - 1);
  const std::array<MeasurementContext, 4> contexts{{
      {Mode::averaging, DisplayMode::range_and_intensity, Units::metres, false},
      {Mode::averaging, DisplayMode::intensity, Units::feet, false},
      {Mode::binning, DisplayMode::range, Units::metres, false},
      {Mode::look_down, DisplayMode::range, Units::metres, true},
  }};
  std::size_t frames = 0;
  std::size_t parsed_frames = 0;
  FrameAssembler assembler(scan_frame, 256);
  std::vector<std::uint8_t> buffer;
  for (int round = 0; round < 100'000; ++round) {
    buffer.resize(static_cast<std::size_t>(length(random)));
    const bool structured = round % 2 == 0;
    for (auto& b : buffer) {
      b = structured ? static_cast<std::uint8_t>(alphabet[pick(random)]) : static_cast<std::uint8_t>(byte(random));
    }
    if (structured && !buffer.empty()) buffer.front() = (round % 4 == 0) ? '$' : '#';

    const Result<FrameView> whole = parse_wire_frame(buffer);
    if (!whole) {
      ASSERT_FALSE(whole.error().message.empty());
    }

    assembler.push(buffer);
    FrameAssembler::Event event;
    while (assembler.next(event)) {
      if (event.kind == FrameAssembler::Event::Kind::rejected) {
        ASSERT_NE(event.reason, nullptr);
        continue;
      }
      ++frames;
      const Result<FrameView> view = parse_frame(event.frame);
      if (!view) {
        ASSERT_EQ(view.error().message.rfind("ULS frame: ", 0), 0U) << view.error().message;
        continue;
      }
      ++parsed_frames;
      const Result<Reply> reply = decode_reply(*view);
      if (!reply) {
        ASSERT_FALSE(reply.error().message.empty());
      }
      for (const MeasurementContext& context : contexts) {
        const Result<Measurement> measurement = decode_measurement(*view, context);
        if (!measurement) {
          ASSERT_FALSE(measurement.error().message.empty());
        }
      }
      (void)validate_request(view->mnemonic, view->fields());
    }
  }
  EXPECT_GT(frames, 1000U);  // the structured half reaches the parser
  EXPECT_GT(parsed_frames, 100U);
}

}  // namespace
}  // namespace rangekit::uls
