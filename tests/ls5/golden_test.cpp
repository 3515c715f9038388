// Golden vectors typed by hand from the LS5 manual; each cites its section.
#include <gtest/gtest.h>

#include "rangekit/ls5/frame.hpp"
#include "rangekit/ls5/parameters.hpp"
#include "rangekit/ls5/reply.hpp"
#include "rangekit/ls5/request.hpp"
#include "test_helpers.hpp"

using namespace rangekit;
using namespace rangekit::ls5;
using ls5_test::bytes_of;
using ls5_test::hex_bytes;
using ls5_test::wire;

// ---- §9.4: the two example sessions, byte for byte ----

TEST(Ls5Golden, TurnOnRequestSection94) {
  // §9.4: #01ON<cr> = 0x23 0x30 0x31 0x4F 0x4E 0x0D
  const auto encoded = encode_request(Request::simple(0x01, CommandId::turn_on));
  ASSERT_TRUE(encoded.ok()) << encoded.error().describe();
  EXPECT_EQ(wire(*encoded), hex_bytes({0x23, 0x30, 0x31, 0x4F, 0x4E, 0x0D}));

  const auto raw = hex_bytes({0x23, 0x30, 0x31, 0x4F, 0x4E, 0x0D});
  const auto parsed = parse_request_line(raw);
  ASSERT_TRUE(parsed.ok()) << parsed.error().describe();
  EXPECT_EQ(parsed->address, 0x01);
  EXPECT_EQ(parsed->command, CommandId::turn_on);
  EXPECT_TRUE(parsed->expects_reply());
}

TEST(Ls5Golden, TurnOnReplySection94) {
  // §9.4: !01ON<cr> = 0x21 0x30 0x31 0x4F 0x4E 0x0D
  const auto encoded = encode_reply(Reply::echo(Request::simple(0x01, CommandId::turn_on)));
  ASSERT_TRUE(encoded.ok()) << encoded.error().describe();
  EXPECT_EQ(wire(*encoded), hex_bytes({0x21, 0x30, 0x31, 0x4F, 0x4E, 0x0D}));

  const auto raw = hex_bytes({0x21, 0x30, 0x31, 0x4F, 0x4E, 0x0D});
  const auto parsed = parse_reply_line(raw);
  ASSERT_TRUE(parsed.ok()) << parsed.error().describe();
  EXPECT_EQ(parsed->kind, ReplyKind::echo);
  EXPECT_EQ(parsed->address, 0x01);
  EXPECT_EQ(parsed->command, CommandId::turn_on);
  EXPECT_TRUE(check_reply_answers(Request::simple(0x01, CommandId::turn_on), *parsed).ok());
}

TEST(Ls5Golden, MedianFilterWriteSection94) {
  // §9.4: #02W0B01<cr> = 0x23 0x30 0x32 0x57 0x30 0x42 0x30 0x31 0x0D; the reply echoes it with '!'.
  const auto request_bytes = hex_bytes({0x23, 0x30, 0x32, 0x57, 0x30, 0x42, 0x30, 0x31, 0x0D});
  const auto reply_bytes = hex_bytes({0x21, 0x30, 0x32, 0x57, 0x30, 0x42, 0x30, 0x31, 0x0D});

  const auto request = parse_request_line(request_bytes);
  ASSERT_TRUE(request.ok()) << request.error().describe();
  EXPECT_EQ(*request, Request::write(0x02, 0x0B, 0x01));
  const auto encoded_request = encode_request(Request::write(0x02, 0x0B, 0x01));
  ASSERT_TRUE(encoded_request.ok());
  EXPECT_EQ(wire(*encoded_request), request_bytes);

  const auto reply = parse_reply_line(reply_bytes);
  ASSERT_TRUE(reply.ok()) << reply.error().describe();
  EXPECT_EQ(reply->kind, ReplyKind::echo);
  EXPECT_EQ(reply->command, CommandId::write_parameter);
  EXPECT_EQ(reply->address, 0x02);
  EXPECT_EQ(reply->parameter, 0x0B);
  EXPECT_EQ(reply->value, 0x01);
  const auto encoded_reply = encode_reply(Reply::echo(*request));
  ASSERT_TRUE(encoded_reply.ok());
  EXPECT_EQ(wire(*encoded_reply), reply_bytes);
  EXPECT_TRUE(check_reply_answers(*request, *reply).ok());
}

// ---- Table 9.1 request and reply forms ----

TEST(Ls5Golden, EveryRequestFormOfTable91) {
  struct Case {
    std::string_view text;
    Request request;
  };
  const Case cases[] = {
      {"#01ID\r", Request::simple(0x01, CommandId::identification)},
      {"#01R05\r", Request::read(0x01, 0x05)},
      {"#01W0506\r", Request::write(0x01, 0x05, 0x06)},
      {"#01FL\r", Request::simple(0x01, CommandId::store_to_flash)},
      {"#01ON\r", Request::simple(0x01, CommandId::turn_on)},
      {"#01OF\r", Request::simple(0x01, CommandId::turn_off)},
      {"#01FX\r", Request::simple(0x01, CommandId::latch_result)},
      {"#01ST\r", Request::simple(0x01, CommandId::start_stream)},
      {"#01SB\r", Request::simple(0x01, CommandId::stop_stream)},
      {"#01FR\r", Request::simple(0x01, CommandId::read_latched)},
      {"#01LR\r", Request::simple(0x01, CommandId::read_last)},
      {"#01DF\r", Request::simple(0x01, CommandId::restore_defaults)},
      // §9.2: "#[AA]W7000<cr>" disables the UDP auto-stream.
      {"#01W7000\r", Request::write(0x01, 0x70, 0x00)},
  };
  for (const Case& c : cases) {
    const auto parsed = parse_request_line(bytes_of(c.text));
    ASSERT_TRUE(parsed.ok()) << c.text << ": " << parsed.error().describe();
    EXPECT_EQ(*parsed, c.request) << c.text;
    const auto encoded = encode_request(c.request);
    ASSERT_TRUE(encoded.ok()) << c.text;
    EXPECT_EQ(encoded->view(), c.text);
  }
}

TEST(Ls5Golden, ReadParameterReply) {
  // Table 9.1: ![AA]Raadd<cr>. Baud rate (05) default 05 (table 9.2).
  const auto reply = parse_reply_line(bytes_of("!01R0505\r"));
  ASSERT_TRUE(reply.ok()) << reply.error().describe();
  EXPECT_EQ(reply->kind, ReplyKind::parameter_value);
  EXPECT_EQ(reply->command, CommandId::read_parameter);
  EXPECT_EQ(reply->parameter, 0x05);
  EXPECT_EQ(reply->value, 0x05);
  EXPECT_TRUE(check_reply_answers(Request::read(0x01, 0x05), *reply).ok());
  EXPECT_FALSE(check_reply_answers(Request::read(0x01, 0x06), *reply).ok());
  const auto encoded = encode_reply(Reply::parameter_value(0x01, 0x05, 0x05));
  ASSERT_TRUE(encoded.ok());
  EXPECT_EQ(encoded->view(), "!01R0505\r");
}

TEST(Ls5Golden, WriteEchoMustRepeatTheValue) {
  const auto reply = parse_reply_line(bytes_of("!02W0B00\r"));
  ASSERT_TRUE(reply.ok());
  const auto answers = check_reply_answers(Request::write(0x02, 0x0B, 0x01), *reply);
  ASSERT_FALSE(answers.ok());
  EXPECT_NE(answers.error().message.find("echoed"), std::string::npos) << answers.error().message;
}

TEST(Ls5Golden, ResultRepliesFrAndLr) {
  // Table 9.1: ![AA]FR[5 bytes of result]<cr>, ![AA]LR[5 bytes of result]<cr>.
  const auto latched = parse_reply_line(bytes_of("!01FR25000\r"));
  ASSERT_TRUE(latched.ok()) << latched.error().describe();
  EXPECT_EQ(latched->kind, ReplyKind::result);
  EXPECT_EQ(latched->command, CommandId::read_latched);
  EXPECT_EQ(latched->result.value, 25000);
  EXPECT_TRUE(latched->result.is_result());

  const auto last = parse_reply_line(bytes_of("!7FLR65535\r"));
  ASSERT_TRUE(last.ok()) << last.error().describe();
  EXPECT_EQ(last->address, 0x7F);
  EXPECT_EQ(last->command, CommandId::read_last);
  EXPECT_EQ(last->result.kind, CodeKind::no_signal);

  const auto encoded = encode_reply(Reply::result_of(0x01, CommandId::read_last, classify_result_code(42)));
  ASSERT_TRUE(encoded.ok());
  EXPECT_EQ(encoded->view(), "!01LR00042\r");
}

// ---- L1: stream records have no address ----

TEST(Ls5Golden, StreamRecordL1) {
  // Table 9.1: ![5 bytes of result]<cr>, 7 bytes (§8.4).
  const auto record = parse_reply_line(bytes_of("!25000\r"));
  ASSERT_TRUE(record.ok()) << record.error().describe();
  EXPECT_EQ(record->kind, ReplyKind::stream_record);
  EXPECT_EQ(record->result.value, 25000);

  const auto encoded = encode_reply(Reply::stream_record(classify_result_code(0)));
  ASSERT_TRUE(encoded.ok());
  EXPECT_EQ(encoded->view(), "!00000\r");
  EXPECT_EQ(encoded->size(), 7U);

  EXPECT_TRUE(check_reply_answers(Request::simple(0x01, CommandId::start_stream), *record).ok());
  EXPECT_FALSE(check_reply_answers(Request::simple(0x01, CommandId::read_last), *record).ok());

  // Same length as an echo, told apart by the digits.
  const auto echo = parse_reply_line(bytes_of("!01SB\r"));
  ASSERT_TRUE(echo.ok());
  EXPECT_EQ(echo->kind, ReplyKind::echo);
  EXPECT_EQ(echo->command, CommandId::stop_stream);

  // Special codes travel in the stream too (§8.9).
  const auto none_yet = parse_reply_line(bytes_of("!65534\r"));
  ASSERT_TRUE(none_yet.ok());
  EXPECT_EQ(none_yet->result.kind, CodeKind::no_measurement_yet);
}

TEST(Ls5Golden, StreamRecordWithWrongDigitCountL1) {
  for (const std::string_view text : {"!2500\r", "!250000\r", "!1\r"}) {
    const auto record = parse_reply_line(bytes_of(text));
    ASSERT_FALSE(record.ok()) << text;
    EXPECT_NE(record.error().message.find("5 digits"), std::string::npos) << record.error().message;
  }
}

TEST(Ls5Golden, StartStreamHasNoEchoL24) {
  const auto reply = parse_reply_line(bytes_of("!01ST\r"));
  ASSERT_FALSE(reply.ok());
  EXPECT_EQ(reply.error().code, Errc::wrong_form);
}

// ---- L2: the identification reply, §9.2 example ----

// §9.2: version LS5.6.0, lower boundary 8,1234 mm, range 40,001 mm (printed "40,0010"),
// serial 157, in the field widths of L2: 10 + 'b' + 6 + 'd' + 7 + "s/n" + 7 = 35.
constexpr std::string_view section_92_field = "LS5.6.0   b8,1234d40,0010s/n0000157";

TEST(Ls5Golden, IdentificationFieldSection92L2) {
  ASSERT_EQ(section_92_field.size(), 35U);
  const auto id = decode_identification_field(section_92_field);
  ASSERT_TRUE(id.ok()) << id.error().describe();
  EXPECT_EQ(id->version_text.view(), "LS5.6.0");
  ASSERT_TRUE(id->version.has_value());
  EXPECT_EQ(*id->version, (FirmwareVersion{6, 0}));
  EXPECT_DOUBLE_EQ(id->lower_boundary_mm, 8.1234);
  EXPECT_DOUBLE_EQ(id->range_mm, 40.001);
  EXPECT_EQ(id->serial_number, 157U);

  const auto encoded = encode_identification_field(*id);
  ASSERT_TRUE(encoded.ok()) << encoded.error().describe();
  EXPECT_EQ(encoded->view(), section_92_field);
}

TEST(Ls5Golden, IdentificationReplySection92L2) {
  const std::string text = "%01" + std::string(section_92_field) + "\r";
  ASSERT_EQ(text.size(), 39U);  // the longest documented frame (F5)
  const auto reply = parse_reply_line(bytes_of(text));
  ASSERT_TRUE(reply.ok()) << reply.error().describe();
  EXPECT_EQ(reply->kind, ReplyKind::identification);
  EXPECT_EQ(reply->address, 0x01);
  EXPECT_EQ(reply->identification.serial_number, 157U);
  EXPECT_DOUBLE_EQ(reply->identification.range_mm, 40.001);
  EXPECT_TRUE(check_reply_answers(Request::simple(0x01, CommandId::identification), *reply).ok());

  const auto encoded = encode_reply(*reply);
  ASSERT_TRUE(encoded.ok()) << encoded.error().describe();
  EXPECT_EQ(encoded->view(), text);

  const auto made = make_identification("LS5.6.0", 8.1234, 40.001, 157);
  ASSERT_TRUE(made.ok()) << made.error().describe();
  const auto from_made = encode_reply(Reply::identification_of(0x01, *made));
  ASSERT_TRUE(from_made.ok());
  EXPECT_EQ(from_made->view(), text);
}

TEST(Ls5Golden, IdentificationIgnoresDamagedSeparatorLettersL2) {
  // The OCR printed "LS5.6.0k o8,1234 d 40,00)10s/ n0000157": the decoder reads by
  // position and does not insist on b, d, s/n.
  const auto id = decode_identification_field("LS5.6.0   k8,1234 40,0010s/ 0000157");
  ASSERT_TRUE(id.ok()) << id.error().describe();
  EXPECT_DOUBLE_EQ(id->lower_boundary_mm, 8.1234);
  EXPECT_DOUBLE_EQ(id->range_mm, 40.001);
  EXPECT_EQ(id->serial_number, 157U);
}

TEST(Ls5Golden, IdentificationAsManyDecimalsAsFitL2) {
  // Table 5.1 sensors: 0.5/5, 700/1000, 250/1000.
  struct Case {
    double lower;
    double range;
    std::string_view field;
  };
  const Case cases[] = {
      {0.5, 5.0, "LS5.9.0   b0,5000d5,00000s/n0000001"},
      {700.0, 1000.0, "LS5.12.3  b700,00d1000,00s/n1234567"},
      {250.0, 2000.0, "LS5.12.3  b250,00d2000,00s/n0000042"},
  };
  const std::string_view versions[] = {"LS5.9.0", "LS5.12.3", "LS5.12.3"};
  const std::uint32_t serials[] = {1, 1234567, 42};
  for (std::size_t i = 0; i < std::size(cases); ++i) {
    const auto made = make_identification(versions[i], cases[i].lower, cases[i].range, serials[i]);
    ASSERT_TRUE(made.ok()) << made.error().describe();
    const auto encoded = encode_identification_field(*made);
    ASSERT_TRUE(encoded.ok());
    EXPECT_EQ(encoded->view(), cases[i].field);
    const auto decoded = decode_identification_field(cases[i].field);
    ASSERT_TRUE(decoded.ok());
    EXPECT_DOUBLE_EQ(decoded->lower_boundary_mm, cases[i].lower);
    EXPECT_DOUBLE_EQ(decoded->range_mm, cases[i].range);
  }
}

TEST(Ls5Golden, IdentificationNumbersThatDoNotFit) {
  EXPECT_FALSE(make_identification("LS5.6.0", 1000000.0, 40.0, 1).ok());  // 7 digits in a 6-character field
  EXPECT_FALSE(make_identification("LS5.6.0", 8.0, 0.0, 1).ok());         // a range of 0
  EXPECT_FALSE(make_identification("LS5.6.0", -1.0, 40.0, 1).ok());
  EXPECT_FALSE(make_identification("LS5.6.0", 8.0, 40.0, 10000000).ok());  // 8-digit serial
  EXPECT_FALSE(make_identification("LS5.6.0.123", 8.0, 40.0, 1).ok());     // 11-character version
}

TEST(Ls5Golden, IdentificationWithUnknownVersionTextL17) {
  const auto id = decode_identification_field("PROTO-7   b8,1234d40,0010s/n0000157");
  ASSERT_TRUE(id.ok()) << id.error().describe();
  EXPECT_EQ(id->version_text.view(), "PROTO-7");
  EXPECT_FALSE(id->version.has_value());
}

TEST(Ls5Golden, IdentificationNumberFieldsWithSpacesL17) {
  const auto id = decode_identification_field("LS5.6.0   b  8,12d   40,0s/n0000157");
  ASSERT_TRUE(id.ok()) << id.error().describe();
  EXPECT_DOUBLE_EQ(id->lower_boundary_mm, 8.12);
  EXPECT_DOUBLE_EQ(id->range_mm, 40.0);
  EXPECT_FALSE(decode_identification_field("LS5.6.0   b8.1234d40,0010s/n0000157").ok());  // decimal point
  EXPECT_FALSE(decode_identification_field("LS5.6.0   b-8,123d40,0010s/n0000157").ok());  // sign
  EXPECT_FALSE(decode_identification_field("LS5.6.0   b8,1234d40,0010s/n00 0157").ok());  // serial digits
}

// ---- L3: addresses ----

TEST(Ls5Golden, AddressesL3) {
  const auto lower = parse_request_line(bytes_of("#fFR0d\r"));
  ASSERT_TRUE(lower.ok()) << lower.error().describe();
  EXPECT_EQ(lower->address, 0xFF);
  EXPECT_EQ(lower->parameter, 0x0D);
  const auto encoded = encode_request(*lower);
  ASSERT_TRUE(encoded.ok());
  EXPECT_EQ(encoded->view(), "#FFR0D\r");  // encoders write upper case

  const auto broadcast = parse_request_line(bytes_of("#00ON\r"));
  ASSERT_TRUE(broadcast.ok());
  EXPECT_TRUE(broadcast->is_broadcast());
  EXPECT_FALSE(broadcast->expects_reply());  // table 9.1 note 2
  EXPECT_FALSE(check_reply_answers(*broadcast, Reply::echo(*broadcast)).ok());

  const auto bad = parse_request_line(bytes_of("#G1ON\r"));
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code, Errc::bad_hex);
  EXPECT_EQ(bad.error().message, "LS5 frame: network address 'G1' is not hex");
}

TEST(Ls5Golden, BroadcastOnlyForNote1CommandsL15) {
  // Table 9.1 note 1 marks W, FL, ON, OF, FX, SB, DF.
  for (const std::string_view text : {"#00W0B01\r", "#00FL\r", "#00ON\r", "#00OF\r", "#00FX\r", "#00SB\r", "#00DF\r"}) {
    const auto parsed = parse_request_line(bytes_of(text));
    ASSERT_TRUE(parsed.ok()) << text << ": " << parsed.error().describe();
    EXPECT_FALSE(parsed->expects_reply()) << text;
  }
  for (const std::string_view text : {"#00ID\r", "#00R05\r", "#00ST\r", "#00FR\r", "#00LR\r"}) {
    const auto parsed = parse_request_line(bytes_of(text));
    ASSERT_FALSE(parsed.ok()) << text;
    EXPECT_EQ(parsed.error().code, Errc::wrong_form) << text;
    EXPECT_NE(parsed.error().message.find("note 1"), std::string::npos) << parsed.error().message;
  }
  EXPECT_FALSE(encode_request(Request::simple(0x00, CommandId::identification)).ok());
  // Nothing answers from 00.
  EXPECT_FALSE(parse_reply_line(bytes_of("!00ON\r")).ok());
  EXPECT_FALSE(encode_reply(Reply::echo(Request::simple(0x00, CommandId::turn_on))).ok());
}

TEST(Ls5Golden, MnemonicsAreUpperCaseL16) {
  const auto parsed = parse_request_line(bytes_of("#01on\r"));
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.error().code, Errc::unknown_command);
  EXPECT_NE(parsed.error().message.find("upper case (ON)"), std::string::npos) << parsed.error().message;
  const auto read = parse_request_line(bytes_of("#01r05\r"));
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.error().message.find("upper case (R)"), std::string::npos) << read.error().message;
}

// ---- L7: result codes on the wire ----

TEST(Ls5Golden, ResultCodesL7) {
  EXPECT_TRUE(parse_reply_line(bytes_of("!00000\r")).ok());
  EXPECT_TRUE(parse_reply_line(bytes_of("!50000\r")).ok());
  EXPECT_TRUE(parse_reply_line(bytes_of("!65534\r")).ok());
  EXPECT_TRUE(parse_reply_line(bytes_of("!65535\r")).ok());
  for (const std::string_view text : {"!50001\r", "!65533\r", "!99999\r", "!01LR50001\r"}) {
    const auto parsed = parse_reply_line(bytes_of(text));
    ASSERT_FALSE(parsed.ok()) << text;
    EXPECT_EQ(parsed.error().code, Errc::out_of_range) << text;
    EXPECT_NE(parsed.error().message.find("is invalid"), std::string::npos) << parsed.error().message;
  }
  Reply bad = Reply::stream_record(ResultCode{50001, CodeKind::result});
  EXPECT_FALSE(encode_reply(bad).ok());
}

// ---- Framing (F1-F5 through the LS5 scan functions) ----

TEST(Ls5Golden, ScanDirections) {
  const auto request = bytes_of("#01ON\r");
  const FrameScan host = scan_request_frame(request);
  EXPECT_EQ(host.status, FrameStatus::complete);
  EXPECT_EQ(as_text(host.frame), "#01ON");
  EXPECT_EQ(host.consumed, 6U);
  // A reply on the request scanner is garbage before a start byte (F2), and vice versa.
  EXPECT_EQ(scan_request_frame(bytes_of("!01ON\r")).status, FrameStatus::invalid);
  EXPECT_EQ(scan_reply_frame(bytes_of("#01ON\r")).status, FrameStatus::invalid);
  EXPECT_EQ(scan_reply_frame(bytes_of("%01LS5")).status, FrameStatus::need_more);
  EXPECT_EQ(scan_reply_frame(bytes_of("!01ON\r")).status, FrameStatus::complete);
}

TEST(Ls5Golden, AssemblerSplitsAReplyStream) {
  FrameAssembler assembler(scan_reply_frame);
  const std::string_view stream = "!01ST\r!25000\r!25001\r\n!65535\r";
  assembler.push(bytes_of(stream));
  FrameAssembler::Event event;
  std::vector<std::string> frames;
  int rejected = 0;
  while (assembler.next(event)) {
    if (event.kind == FrameAssembler::Event::Kind::frame) {
      frames.emplace_back(as_text(event.frame));
    } else {
      ++rejected;
    }
  }
  EXPECT_EQ(rejected, 0);
  ASSERT_EQ(frames.size(), 4U);
  EXPECT_FALSE(parse_reply(bytes_of(frames[0])).ok());  // ST has no echo
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const auto record = parse_reply(bytes_of(frames[i]));
    ASSERT_TRUE(record.ok()) << frames[i];
    EXPECT_EQ(record->kind, ReplyKind::stream_record);
  }
}

// ---- L14: syntax only; the table check is separate ----

TEST(Ls5Golden, WellFormedRequestsForUnknownParametersParseL14) {
  // 0F is not in table 9.2 and 09 is not a baud code, but both frames are well formed:
  // the codec parses them and check_parameter_byte says what is wrong.
  const auto unknown = parse_request_line(bytes_of("#01R0F\r"));
  ASSERT_TRUE(unknown.ok()) << unknown.error().describe();
  EXPECT_EQ(unknown->parameter, 0x0F);
  EXPECT_EQ(check_parameter_available(0x0F, SensorModel{}).error().code, Errc::unknown_parameter);

  const auto bad_baud = parse_request_line(bytes_of("#01W0509\r"));
  ASSERT_TRUE(bad_baud.ok()) << bad_baud.error().describe();
  const auto check = check_parameter_byte(bad_baud->parameter, bad_baud->value, SensorModel{});
  ASSERT_FALSE(check.ok());
  EXPECT_EQ(check.error().code, Errc::out_of_range);
  EXPECT_EQ(check.error().message,
            "LS5 parameter 05 (Baud rate) does not accept 09; accepted: 01-05; 06-08 from LS5.6.0");
}
