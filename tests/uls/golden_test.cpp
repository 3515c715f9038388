// Golden vectors typed by hand from the ULS document (uls-interface-spec.txt).
// Each test cites the section it comes from and the conformance row it holds.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "rangekit/uls/uls.hpp"
#include "uls/test_support.hpp"

namespace rangekit::uls {
namespace {

using testing::fields_joined;
using testing::must_parse;
using testing::wire_of;

// ---------------------------------------------------------------------------
// §8 Message Format examples
// ---------------------------------------------------------------------------

TEST(UlsGolden, AddressableSetExample) {  // §8 "#ZMM,1 Set ULS with address 0x5a ('Z') to Averaging Mode"
  const FrameView view = must_parse("#ZMM,1");
  EXPECT_TRUE(view.address.addressed);
  EXPECT_EQ(view.address.byte, 0x5A);
  EXPECT_EQ(view.mnemonic, "MM");
  EXPECT_EQ(fields_joined(view), "1");
  const std::string_view one = "1";
  EXPECT_EQ(wire_of(encode_set(Address::unit('Z'), "MM", {&one, 1})), "#ZMM,1\r");
  EXPECT_EQ(wire_of(encode_set(Address::unit(0x5A), "MM", 1)), "#ZMM,1\r");
}

TEST(UlsGolden, AddressableGetAndReplyExample) {  // §8 "#ZMM" get, "#ZMM,1" reply
  const FrameView get = must_parse("#ZMM");
  EXPECT_EQ(get.address, Address::unit('Z'));
  EXPECT_EQ(get.field_count, 0U);
  EXPECT_EQ(wire_of(encode_get(Address::unit('Z'), "MM")), "#ZMM\r");

  const Result<Reply> reply = decode_reply(as_bytes("#ZMM,1"));
  ASSERT_TRUE(reply.ok()) << reply.error().describe();
  EXPECT_EQ(reply->kind, ReplyKind::value);
  EXPECT_EQ(reply->source, Address::unit('Z'));
  ASSERT_NE(reply->command, nullptr);
  EXPECT_EQ(reply->command->mnemonic, "MM");
  ASSERT_EQ(reply->values().size(), 1U);
  EXPECT_EQ(reply->values()[0], "1");
}

TEST(UlsGolden, NonAddressableExamples) {  // §8 "$MM" get, "$MM,1<CR>" reply, "$OK<CR>", "$ER,n<CR>"
  EXPECT_EQ(wire_of(encode_get(Address::none(), "MM")), "$MM\r");
  EXPECT_EQ(wire_of(encode_value_reply(Address::none(), "MM", std::array<std::string_view, 1>{"1"})), "$MM,1\r");
  EXPECT_EQ(wire_of(encode_ok(Address::none())), "$OK\r");
  EXPECT_EQ(wire_of(encode_error_reply(Address::none(), 85)), "$ER,85\r");
  EXPECT_EQ(wire_of(encode_ok(Address::unit('Z'))), "#ZOK\r");
  EXPECT_EQ(wire_of(encode_error_reply(Address::unit('Z'), 1)), "#ZER,1\r");

  const Result<Reply> ok = decode_reply(as_bytes("$OK"));
  ASSERT_TRUE(ok.ok());
  EXPECT_EQ(ok->kind, ReplyKind::ok);
  EXPECT_FALSE(ok->source.addressed);

  const Result<Reply> error = decode_reply(as_bytes("#ZER,31"));
  ASSERT_TRUE(error.ok());
  EXPECT_EQ(error->kind, ReplyKind::error);
  EXPECT_EQ(error->error_number, 31);
  ASSERT_NE(error->error, nullptr);
  EXPECT_EQ(error->error->display, "Instrument Is Already Measuring");
}

// ---------------------------------------------------------------------------
// §8 ULS Commands: every command's forms, typed from its page, round-tripped
// ---------------------------------------------------------------------------

struct CommandForms {
  std::string_view mnemonic;
  std::string_view set;    // empty: no set form
  std::string_view get;    // empty: no get form (action commands list theirs here too)
  std::string_view reply;  // value reply to the get, empty when none
};

// Values are the document's own where it gives one (§2 screens, §6 example, §3).
constexpr std::array<CommandForms, 37> forms{{
    {"DD", "$DD,1", "$DD", "$DD,1"},                            // p.25 (U1: "$1DD,n" is a slip)
    {"BM", "", "$BM", "$BM,12.345"},                            // p.25, averaging range reply
    {"ID", "", "$ID", "$ID,ULS version number date"},           // p.25
    {"US", "", "$US", "$US,7"},                                 // p.26
    {"MA", "$MA,1", "$MA", "$MA,0"},                            // p.26
    {"GO", "", "$GO", ""},                                      // p.26 action
    {"ST", "", "$ST", ""},                                      // p.27 action
    {"PA", "$PA,1", "$PA", "$PA,1"},                            // p.27
    {"PT", "$PT,1", "", ""},                                    // p.27 set only (U16)
    {"SU", "", "$SU", ""},                                      // p.27 action
    {"CL", "$CL,1", "$CL", "$CL,0"},                            // p.28
    {"AW", "$AW,992", "$AW", "$AW,992"},                        // p.28, §2 screen "992"
    {"BR", "$BR,0,115200", "$BR,0", "$BR,0,115200"},            // p.28, §8 default 115200
    {"BS", "$BS,0", "$BS", "$BS,0"},                            // p.29
    {"BH", "$BH,128", "$BH", "$BH,128"},                        // p.29, §2 "Bin Hits 128"
    {"CO", "$CO,1", "$CO", "$CO,1"},                            // p.29
    {"FL", "$FL,0", "$FL", "$FL,0"},                            // p.30
    {"DM", "$DM,2", "$DM", "$DM,2"},                            // p.30
    {"AF", "$AF,3.0", "$AF", "$AF,3.0"},                        // p.30, §6 "Fault Indication 3.0 mA"
    {"AT", "$AT,0.0", "$AT", "$AT,0.0"},                        // p.31, §6 "Fault Timeout 0.0 secs"
    {"LG", "$LG,100", "$LG", "$LG,100.000"},                    // p.31, §2 "100 m"
    {"MM", "$MM,1", "$MM", "$MM,1"},                            // p.31, §8 example
    {"MO", "$MO,0", "$MO", "$MO,0"},                            // p.32
    {"MU", "$MU,1", "$MU", "$MU,1"},                            // p.32
    {"PL", "$PL,0", "$PL", "$PL,0"},                            // p.32
    {"PF", "$PF,2000", "$PF", "$PF,2000,1000,3000"},            // p.33, §2 "PRF 2000", §9 1000 binning
    {"PF", "$PF,3000,1000,3000", "$PF", "$PF,3000,1000,3000"},  // p.33 three-value form (U14)
    {"PO", "$PO,1024,100", "$PO", "$PO,1024,100"},              // p.33, §2 "1024", §9 100 binning
    {"AH", "$AH,10.000", "$AH", "$AH,10.000"},                  // p.33, §6 "Distance at 20mA 10.000 M"
    {"AL", "$AL,0.000", "$AL", "$AL,0.000"},                    // p.34, §6 "Distance at 4mA 0.000 M"
    {"TE", "$TE,1", "$TE", "$TE,1"},                            // p.34
    {"SG", "$SG,10", "$SG", "$SG,10.000"},                      // p.34, §2 "10 m"
    {"TB", "$TB,1", "$TB", "$TB,1"},                            // p.35
    {"TP", "$TP,0.2", "$TP", "$TP,0.200"},                      // p.35, §2 "Trip Point 0.2 M"
    {"TT", "$TT,107AC0", "$TT", "$TT,107AC0"},                  // p.35, U21
    {"UA", "$UA,Z", "$UA", "$UA,90"},                           // p.36, table "Z = 90"
    {"OF", "$OF,-1.500", "$OF", "$OF,-1.500"},                  // p.36, "can be positive or negative" (§2)
}};

// Parse, then encode what was parsed with the given address; compare with the text.
void expect_round_trip(std::string_view dollar_frame, Address address, std::string_view expected_wire) {
  const FrameView view = must_parse(dollar_frame);
  const Result<FrameText> encoded = encode_frame(address, view.mnemonic, view.fields());
  EXPECT_EQ(wire_of(encoded), expected_wire) << dollar_frame;
  if (!encoded) return;
  const FrameView again = must_parse(encoded->frame());
  EXPECT_EQ(again.address, address);
  EXPECT_EQ(again.mnemonic, view.mnemonic);
  EXPECT_EQ(fields_joined(again), fields_joined(view));
}

std::string with_address(std::string_view dollar_frame, char address) {
  std::string text = "#";
  text += address;
  text += dollar_frame.substr(1);
  return text;
}

TEST(UlsGolden, EveryCommandHasItsForms) {
  std::vector<std::string_view> covered;
  for (const CommandForms& row : forms) covered.push_back(row.mnemonic);
  for (const CommandInfo& command : command_table()) {
    EXPECT_NE(std::find(covered.begin(), covered.end(), command.mnemonic), covered.end()) << command.mnemonic;
  }
}

TEST(UlsGolden, EveryCommandRoundTripsInBothAddressingForms) {
  for (const CommandForms& row : forms) {
    for (const std::string_view frame : {row.set, row.get, row.reply}) {
      if (frame.empty()) continue;
      SCOPED_TRACE(std::string(frame));
      expect_round_trip(frame, Address::none(), std::string(frame) + "\r");
      expect_round_trip(frame, Address::unit('Z'), with_address(frame, 'Z') + "\r");
      expect_round_trip(frame, Address::unit('0'), with_address(frame, '0') + "\r");
    }
    // Requests may go to every unit at once (§8 RS485 Protocol, U4).
    for (const std::string_view request : {row.set, row.get}) {
      if (request.empty()) continue;
      SCOPED_TRACE(std::string(request));
      expect_round_trip(request, Address::broadcast(0xF0), with_address(request, '\xF0') + "\r");
      expect_round_trip(request, Address::broadcast(0xFF), with_address(request, '\xFF') + "\r");
    }
  }
}

TEST(UlsGolden, EveryRequestPassesTheTableAndEveryReplyDecodes) {
  for (const CommandForms& row : forms) {
    SCOPED_TRACE(std::string(row.mnemonic));
    const CommandInfo* command = find_command(row.mnemonic);
    ASSERT_NE(command, nullptr);
    if (!row.set.empty()) {
      const FrameView set = must_parse(row.set);
      EXPECT_EQ(request_form(*command, set.field_count).form, RequestForm::set);
      EXPECT_EQ(validate_request(*command, set.fields()), Verdict::accept());
    }
    if (!row.get.empty()) {
      const FrameView get = must_parse(row.get);
      const RequestForm expected = command->access == Access::action ? RequestForm::action : RequestForm::get;
      EXPECT_EQ(request_form(*command, get.field_count).form, expected);
      EXPECT_EQ(validate_request(*command, get.fields()), Verdict::accept());
    }
    if (!row.reply.empty()) {
      const Result<Reply> reply = decode_reply(as_bytes(row.reply));
      ASSERT_TRUE(reply.ok()) << reply.error().describe();
      EXPECT_EQ(reply->kind, ReplyKind::value);
      EXPECT_EQ(reply->command, command);
    }
  }
}

TEST(UlsGolden, BroadcastAddressesCarryCommandsButNoReplies) {  // §8 RS485 Protocol, U4
  for (const int address : {0xF0, 0xF7, 0xFF}) {
    const auto byte = static_cast<std::uint8_t>(address);
    const std::string expected = std::string("#") + static_cast<char>(byte) + "GO\r";
    EXPECT_EQ(wire_of(encode_action(Address::broadcast(byte), "GO")), expected);
    const FrameView view = must_parse(std::string_view(expected).substr(0, expected.size() - 1));
    EXPECT_TRUE(view.address.is_broadcast());
    EXPECT_FALSE(view.address.is_unit());

    const std::string reply = std::string("#") + static_cast<char>(byte) + "OK";
    const Result<Reply> decoded = decode_reply(as_bytes(reply));
    ASSERT_FALSE(decoded.ok());
    EXPECT_EQ(decoded.error().code, Errc::wrong_form);
    EXPECT_NE(decoded.error().message.find("broadcast"), std::string::npos);
  }
  EXPECT_TRUE(Address::unit(0x30).is_unit());
  EXPECT_TRUE(Address::unit(0xEF).is_unit());
  EXPECT_FALSE(Address::unit(0xEF).is_broadcast());
}

TEST(UlsGolden, AddressBelow0x30IsInvalid) {  // §8 "a = one byte hexadecimal unit address 0x30 to 0xff", U4
  const Result<FrameView> parsed = parse_frame(std::string_view("#/MM,1"));  // '/' = 0x2F
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.error().code, Errc::invalid_frame);
  EXPECT_EQ(parsed.error().message, "ULS frame: address byte 0x2F below 0x30");
  const Result<FrameText> encoded = encode_get(Address::unit(0x2F), "MM");
  ASSERT_FALSE(encoded.ok());
  EXPECT_NE(encoded.error().message.find("0x2F below 0x30"), std::string::npos);
}

// ---------------------------------------------------------------------------
// Conformance rows held here
// ---------------------------------------------------------------------------

TEST(UlsConformance, U1_DitherReplyIsPlainDD) {  // §8 Dither Get reply printed "$1DD,n"
  const Result<Reply> reply = decode_reply(as_bytes("$DD,1"));
  ASSERT_TRUE(reply.ok());
  EXPECT_EQ(reply->command->mnemonic, "DD");
  const Result<FrameView> slip = parse_frame(std::string_view("$1DD,1"));
  ASSERT_FALSE(slip.ok());
  EXPECT_NE(slip.error().message.find("non-letter"), std::string::npos);
}

TEST(UlsConformance, U2_AddressedVersionReplyStartsWithHash) {  // §8 Get Software Version
  const Result<Reply> reply = decode_reply(as_bytes("#ZID,ULS version number date"));
  ASSERT_TRUE(reply.ok()) << reply.error().describe();
  EXPECT_EQ(reply->source, Address::unit('Z'));
  EXPECT_EQ(reply->command->mnemonic, "ID");
  EXPECT_EQ(reply->values()[0], "ULS version number date");
  // Free text up to the frame limit: a version with commas is split, still one reply.
  const Result<Reply> split = decode_reply(as_bytes("$ID,ULS 0.97,March 2005"));
  ASSERT_TRUE(split.ok());
  EXPECT_EQ(split->values().size(), 2U);
}

TEST(UlsConformance, U3_UnassignedUnitAnswers82) {  // §8 RS485, §10 "82 Unit Address Not Assigned"
  EXPECT_EQ(wire_of(encode_get(Address::none(), "UA")), "$UA\r");
  const Result<Reply> reply = decode_reply(as_bytes("$ER,82"));
  ASSERT_TRUE(reply.ok());
  EXPECT_EQ(reply->error_number, 82);
  ASSERT_NE(reply->error, nullptr);
  EXPECT_EQ(reply->error->display, "Unit Address Not Assigned");
  // '0' (0x30) is a valid address character, unlike the factory value zero.
  EXPECT_TRUE(Address::unit('0').is_unit());
  EXPECT_TRUE(parse_frame(std::string_view("#0US")).ok());
}

TEST(UlsConformance, U4_AddressRanges) {  // §8 RS485 Protocol
  EXPECT_EQ(first_unit_address, 0x30);
  EXPECT_EQ(last_unit_address, 0xEF);
  EXPECT_EQ(first_broadcast_address, 0xF0);
  for (int byte = 0; byte < 0x30; ++byte) {
    if (byte == '\r') continue;
    std::string frame = "#";
    frame += static_cast<char>(byte);
    frame += "US";
    EXPECT_FALSE(parse_frame(std::string_view(frame)).ok()) << byte;
  }
  for (int byte = 0x30; byte <= 0xFF; ++byte) {
    std::string frame = "#";
    frame += static_cast<char>(byte);
    frame += "US";
    const Result<FrameView> parsed = parse_frame(std::string_view(frame));
    ASSERT_TRUE(parsed.ok()) << byte;
    EXPECT_EQ(parsed->address.is_broadcast(), byte >= 0xF0) << byte;
  }
}

// §8 Set/Get Unit Address, "Equivalent values for aa and ad", typed as printed.
struct AddressEntry {
  char character;
  int printed;
};
// Laid out as the document prints it, column by column; y and z are the misprints of U5.
// clang-format off
constexpr std::array<AddressEntry, 62> printed_address_table{{
    {'a', 97},  {'b', 98},  {'c', 99},  {'d', 100}, {'e', 101}, {'f', 102}, {'g', 103},
    {'h', 104}, {'i', 105}, {'j', 106}, {'k', 107}, {'l', 108}, {'m', 109},
    {'n', 110}, {'o', 111}, {'p', 112}, {'q', 113}, {'r', 114}, {'s', 115}, {'t', 116},
    {'u', 117}, {'v', 118}, {'w', 119}, {'x', 120}, {'y', 122}, {'z', 123},
    {'A', 65},  {'B', 66},  {'C', 67},  {'D', 68},  {'E', 69},  {'F', 70},  {'G', 71},
    {'H', 72},  {'I', 73},  {'J', 74},  {'K', 75},  {'L', 76},  {'M', 77},
    {'N', 78},  {'O', 79},  {'P', 80},  {'Q', 81},  {'R', 82},  {'S', 83},  {'T', 84},
    {'U', 85},  {'V', 86},  {'W', 87},  {'X', 88},  {'Y', 89},  {'Z', 90},
    {'0', 48},  {'1', 49},  {'2', 50},  {'3', 51},  {'4', 52},  {'5', 53},  {'6', 54},
    {'7', 55},  {'8', 56},  {'9', 57},
}};
// clang-format on

TEST(UlsConformance, U5_UnitAddressTable) {
  const CommandInfo& ua = *find_command("UA");
  for (const AddressEntry& entry : printed_address_table) {
    SCOPED_TRACE(std::string(1, entry.character));
    int expected = entry.printed;
    if (entry.character == 'y') expected = 121;  // U5: ASCII, the table prints 122
    if (entry.character == 'z') expected = 122;  // U5: ASCII, the table prints 123
    const auto byte = static_cast<std::uint8_t>(entry.character);
    EXPECT_EQ(unit_address_value(byte), expected);
    EXPECT_EQ(unit_address_char(static_cast<std::uint64_t>(expected)), byte);
    // Set carries the character, the get reply the decimal value.
    const std::string_view set_value(&entry.character, 1);
    EXPECT_EQ(validate_request(ua, {&set_value, 1}), Verdict::accept());
    const std::string reply = "$UA," + std::to_string(expected);
    EXPECT_TRUE(decode_reply(as_bytes(reply)).ok()) << reply;
  }
  EXPECT_FALSE(unit_address_char(0x2F).has_value());
  EXPECT_FALSE(unit_address_char(0xF0).has_value());
  EXPECT_EQ(unit_address_char(0xEF), 0xEF);
}

TEST(UlsConformance, U6_UnitStatusValuesAreBitSums) {  // §8 Get Unit Status and its #defines
  EXPECT_EQ(status_bit::active, 0x01);
  EXPECT_EQ(status_bit::laser_firing, 0x02);
  EXPECT_EQ(status_bit::averaging_calc, 0x04);
  EXPECT_EQ(status_bit::binning_calc, 0x08);
  EXPECT_EQ(wire_value(UnitStatus::error), 0);
  EXPECT_EQ(wire_value(UnitStatus::ready), 1);
  EXPECT_EQ(wire_value(UnitStatus::look_down), 3);
  EXPECT_EQ(wire_value(UnitStatus::averaging), 7);
  EXPECT_EQ(wire_value(UnitStatus::binning), 11);
  EXPECT_EQ(status_mode(UnitStatus::averaging), Mode::averaging);
  EXPECT_EQ(status_mode(UnitStatus::binning), Mode::binning);
  EXPECT_EQ(status_mode(UnitStatus::look_down), Mode::look_down);
  EXPECT_FALSE(status_mode(UnitStatus::ready).has_value());
  EXPECT_FALSE(status_firing(UnitStatus::ready));
  EXPECT_TRUE(status_firing(UnitStatus::look_down));
  EXPECT_EQ(status_for(true, Mode::binning), UnitStatus::binning);
  EXPECT_EQ(status_for(false, Mode::binning), UnitStatus::ready);
  for (const int value : {0, 1, 3, 7, 11}) EXPECT_TRUE(to_unit_status(value).has_value()) << value;
  for (const int value : {2, 4, 5, 6, 8, 9, 10, 12, 15}) EXPECT_FALSE(to_unit_status(value).has_value()) << value;
  EXPECT_TRUE(decode_reply(as_bytes("$US,11")).ok());
  EXPECT_FALSE(decode_reply(as_bytes("$US,2")).ok());
}

TEST(UlsConformance, U7_MeasurementModeNumbers) {  // §8 Set/Get Measurement Mode, example "#ZMM,1" = Averaging
  EXPECT_EQ(to_mode(1), Mode::averaging);
  EXPECT_EQ(to_mode(2), Mode::binning);
  EXPECT_EQ(to_mode(3), Mode::look_down);
  EXPECT_FALSE(to_mode(0).has_value());
  EXPECT_FALSE(to_mode(4).has_value());
  const std::string_view four = "4";
  EXPECT_EQ(validate_request("MM", {&four, 1}).error, 85);  // Invalid Measurement Mode
  EXPECT_EQ(find_command("MM")->value_name(1), "averaging");
}

MeasurementContext averaging(DisplayMode display, Units units = Units::metres) {
  return {Mode::averaging, display, units, false};
}

TEST(UlsConformance, U8_PulseWidthIsPicoseconds) {  // §9 "yyyyyyy = pulse width (pico seconds)"
  const Result<Measurement> line =
      decode_measurement(as_bytes("$BM,12.345,8250"), averaging(DisplayMode::range_and_intensity));
  ASSERT_TRUE(line.ok()) << line.error().describe();
  const auto& reading = std::get<AveragingReading>(line->reading);
  EXPECT_EQ(reading.pulse_width_ps, 8250U);
  EXPECT_DOUBLE_EQ(*reading.pulse_width_ns(), 8.25);
  EXPECT_DOUBLE_EQ(reading.range->metres, 12.345);
}

TEST(UlsConformance, U9_AveragingLinesFollowDisplayModeAndUnits) {  // §8 "$BM,n / $BM,p / $BM,n,p", §9 decimals
  const Result<Measurement> range = decode_measurement(as_bytes("$BM,12.345"), averaging(DisplayMode::range));
  ASSERT_TRUE(range.ok());
  const auto& metres = std::get<AveragingReading>(range->reading);
  EXPECT_DOUBLE_EQ(metres.range->user, 12.345);
  EXPECT_FALSE(metres.pulse_width_ps.has_value());

  const Result<Measurement> feet =
      decode_measurement(as_bytes("$BM,40.50"), averaging(DisplayMode::range, Units::feet));
  ASSERT_TRUE(feet.ok());
  const Range& in_feet = *std::get<AveragingReading>(feet->reading).range;
  EXPECT_DOUBLE_EQ(in_feet.user, 40.5);
  EXPECT_NEAR(in_feet.metres, 12.3444, 1e-9);  // 40.5 ft x 0.3048
  EXPECT_EQ(in_feet.units, Units::feet);

  const Result<Measurement> width = decode_measurement(as_bytes("$BM,8250"), averaging(DisplayMode::intensity));
  ASSERT_TRUE(width.ok());
  EXPECT_FALSE(std::get<AveragingReading>(width->reading).range.has_value());
  EXPECT_EQ(std::get<AveragingReading>(width->reading).pulse_width_ps, 8250U);

  // Wrong against the context: each names the problem.
  const auto wrong = [](std::string_view frame, MeasurementContext context) {
    const Result<Measurement> decoded = decode_measurement(as_bytes(frame), context);
    EXPECT_FALSE(decoded.ok()) << frame;
    return decoded.ok() ? std::string() : decoded.error().message;
  };
  EXPECT_NE(wrong("$BM,12.34", averaging(DisplayMode::range)).find("has 2 decimals; metres are written with 3"),
            std::string::npos);
  EXPECT_NE(wrong("$BM,12.345", averaging(DisplayMode::range, Units::feet)).find("feet"), std::string::npos);
  EXPECT_NE(wrong("$BM,8250", averaging(DisplayMode::range)).find("no decimal point"), std::string::npos);
  EXPECT_NE(wrong("$BM,12.345", averaging(DisplayMode::intensity)).find("decimal point"), std::string::npos);
  EXPECT_NE(wrong("$BM,12.345", averaging(DisplayMode::range_and_intensity)).find("1 fields, needs 2"),
            std::string::npos);

  EXPECT_EQ(wire_of(encode_averaging(Address::none(), {make_range(12.345, Units::metres), std::nullopt})),
            "$BM,12.345\r");
  EXPECT_EQ(wire_of(encode_averaging(Address::none(), {make_range(40.5, Units::feet), std::nullopt})), "$BM,40.50\r");
  EXPECT_EQ(wire_of(encode_averaging(Address::none(), {std::nullopt, 8250U})), "$BM,8250\r");
  EXPECT_EQ(wire_of(encode_averaging(Address::unit('Z'), {make_range(0.15, Units::metres), 8250U})),
            "#ZBM,0.150,8250\r");
}

TEST(UlsConformance, U10_BinningLineUsesUserUnits) {  // §8 "$BM,i,m,n,s", §9 "$BM,I,A,xxxx.xxx,SSS"
  const MeasurementContext metres{Mode::binning, DisplayMode::range, Units::metres, false};
  const Result<Measurement> first = decode_measurement(as_bytes("$BM,0,2,12.345,57"), metres);
  ASSERT_TRUE(first.ok()) << first.error().describe();
  const auto& target = std::get<BinningTarget>(first->reading);
  EXPECT_EQ(target.index, 0);
  EXPECT_EQ(target.count, 2);
  EXPECT_DOUBLE_EQ(target.range.metres, 12.345);
  EXPECT_EQ(target.strength, 57U);

  const MeasurementContext feet{Mode::binning, DisplayMode::range, Units::feet, false};
  const Result<Measurement> in_feet = decode_measurement(as_bytes("#ZBM,1,2,40.50,128"), feet);
  ASSERT_TRUE(in_feet.ok());
  EXPECT_EQ(in_feet->source, Address::unit('Z'));
  EXPECT_DOUBLE_EQ(std::get<BinningTarget>(in_feet->reading).range.user, 40.5);

  EXPECT_FALSE(decode_measurement(as_bytes("$BM,2,2,12.345,57"), metres).ok());   // index not below count
  EXPECT_FALSE(decode_measurement(as_bytes("$BM,0,16,12.345,57"), metres).ok());  // more than 15 targets
  EXPECT_FALSE(decode_measurement(as_bytes("$BM,0,2,12345,57"), metres).ok());    // millimetres: no point

  const BinningTarget written{0, 2, make_range(12.345, Units::metres), 57};
  EXPECT_EQ(wire_of(encode_binning_target(Address::none(), written)), "$BM,0,2,12.345,57\r");
}

TEST(UlsConformance, U11_SameLineReadsByContext) {  // §8: "$BM,1" is look-down ON, or a 1 ps pulse width
  const MeasurementContext look_down{Mode::look_down, DisplayMode::range, Units::metres, false};
  const Result<Measurement> on = decode_measurement(as_bytes("$BM,1"), look_down);
  ASSERT_TRUE(on.ok());
  EXPECT_TRUE(std::get<LookDownReading>(on->reading).present);
  const Result<Measurement> off = decode_measurement(as_bytes("$BM,0"), look_down);
  ASSERT_TRUE(off.ok());
  EXPECT_FALSE(std::get<LookDownReading>(off->reading).present);
  EXPECT_FALSE(decode_measurement(as_bytes("$BM,2"), look_down).ok());

  const Result<Measurement> width = decode_measurement(as_bytes("$BM,1"), averaging(DisplayMode::intensity));
  ASSERT_TRUE(width.ok());
  EXPECT_EQ(std::get<AveragingReading>(width->reading).pulse_width_ps, 1U);
  EXPECT_FALSE(decode_measurement(as_bytes("$BM,1"), averaging(DisplayMode::range)).ok());

  EXPECT_EQ(wire_of(encode_look_down(Address::none(), true)), "$BM,1\r");
  EXPECT_EQ(wire_of(encode_look_down(Address::unit('Z'), false)), "#ZBM,0\r");
}

const MeasurementContext events{Mode::look_down, DisplayMode::range, Units::metres, true};

TEST(UlsConformance, U12_TimeBetweenEvents) {  // §3 "0BB8 hex (3000 decimal) ... equaled 1 second", §8 "$n/$XXXX"
  const FrameView view = must_parse("$0BB8");
  EXPECT_EQ(view.kind, FrameKind::time_between_events);
  EXPECT_EQ(view.event_text, "0BB8");
  const Result<Measurement> gap = decode_measurement(view, events);
  ASSERT_TRUE(gap.ok()) << gap.error().describe();
  const auto& event = std::get<TimeBetweenEvents>(gap->reading);
  EXPECT_EQ(event.kind, TimeBetweenEvents::Kind::pulses);
  EXPECT_EQ(event.pulses, 3000);
  EXPECT_DOUBLE_EQ(*tbe_seconds(event, 3000), 1.0);

  const Result<Measurement> none = decode_measurement(as_bytes("$0"), events);
  ASSERT_TRUE(none.ok());
  EXPECT_EQ(std::get<TimeBetweenEvents>(none->reading).kind, TimeBetweenEvents::Kind::no_presence);

  const Result<Measurement> overflow = decode_measurement(as_bytes("#Z0000"), events);  // §8 "set to 0000 hex"
  ASSERT_TRUE(overflow.ok());
  EXPECT_EQ(overflow->source, Address::unit('Z'));
  EXPECT_EQ(std::get<TimeBetweenEvents>(overflow->reading).kind, TimeBetweenEvents::Kind::overflow);

  const Result<Measurement> longest = decode_measurement(as_bytes("$FFFF"), events);  // "maximum value of FFFF hex"
  ASSERT_TRUE(longest.ok());
  EXPECT_EQ(std::get<TimeBetweenEvents>(longest->reading).pulses, 65535);

  using Kind = TimeBetweenEvents::Kind;
  EXPECT_EQ(wire_of(encode_time_between_events(Address::none(), {Kind::pulses, 3000})), "$0BB8\r");
  EXPECT_EQ(wire_of(encode_time_between_events(Address::none(), {Kind::no_presence, 0})), "$0\r");
  EXPECT_EQ(wire_of(encode_time_between_events(Address::unit('Z'), {Kind::overflow, 0})), "#Z0000\r");
  EXPECT_EQ(wire_of(encode_time_between_events(Address::unit('Z'), {Kind::no_presence, 0})), "#Z0\r");
  EXPECT_FALSE(encode_time_between_events(Address::none(), {Kind::pulses, 0}).ok());
  // Not exactly four digits: neither an event nor a mnemonic.
  EXPECT_FALSE(parse_frame(std::string_view("$0BB")).ok());
  EXPECT_FALSE(parse_frame(std::string_view("$00BB8")).ok());
}

TEST(UlsConformance, U13_StreamedErrorsAreErLines) {  // §8 "Reply: $ER,n", §6 errors 4 and 5
  for (const MeasurementContext& context : {averaging(DisplayMode::range), events}) {
    const Result<Measurement> four = decode_measurement(as_bytes("$ER,4"), context);
    ASSERT_TRUE(four.ok());
    EXPECT_EQ(std::get<MeasurementError>(four->reading).number, 4);
    const Result<Measurement> five = decode_measurement(as_bytes("#ZER,5"), context);
    ASSERT_TRUE(five.ok());
    EXPECT_EQ(std::get<MeasurementError>(five->reading).number, 5);
  }
  EXPECT_EQ(wire_of(encode_measurement_error(Address::none(), 4)), "$ER,4\r");
  EXPECT_EQ(wire_of(encode_measurement(Address::unit('Z'), MeasurementError{5})), "#ZER,5\r");
}

TEST(UlsConformance, U14_PrfOneOrThreeValues) {  // §8 Set/Get PRF note: "Averaging,Binning,Look Down"
  const CommandInfo& pf = *find_command("PF");
  const std::array<std::string_view, 3> three{"3000", "1000", "3000"};
  EXPECT_EQ(validate_request(pf, three), Verdict::accept());
  EXPECT_EQ(validate_request(pf, std::span(three).first(1)), Verdict::accept());
  EXPECT_EQ(validate_request(pf, std::span(three).first(2)).error, 1);
  const std::array<std::string_view, 1> too_fast{"5001"};
  EXPECT_EQ(validate_request(pf, too_fast).error, 32);  // Invalid Rep Rate
  const std::array<std::string_view, 3> one_slow{"3000", "9", "3000"};
  EXPECT_EQ(validate_request(pf, one_slow).error, 32);
  const std::array<std::string_view, 1> edges_low{"10"};
  const std::array<std::string_view, 1> edges_high{"5000"};
  EXPECT_TRUE(validate_request(pf, edges_low).ok());
  EXPECT_TRUE(validate_request(pf, edges_high).ok());
  EXPECT_FALSE(decode_reply(as_bytes("$PF,2000")).ok());  // the get reply always carries three
}

TEST(UlsConformance, U15_PpmOneOrTwoValues) {  // §8 Set/Get Pulses Per Measurement
  const CommandInfo& po = *find_command("PO");
  const std::array<std::string_view, 2> two{"1024", "100"};
  EXPECT_TRUE(validate_request(po, two).ok());
  EXPECT_TRUE(validate_request(po, std::span(two).first(1)).ok());
  const std::array<std::string_view, 3> three{"1024", "100", "30"};
  EXPECT_EQ(validate_request(po, three).error, 1);
  const std::array<std::string_view, 1> zero{"0"};
  const std::array<std::string_view, 1> huge{"65536"};
  EXPECT_EQ(validate_request(po, zero).error, 1);
  EXPECT_EQ(validate_request(po, huge).error, 1);
  EXPECT_EQ(check_ppm_against_weight(1024, 992), Verdict::accept());  // §2 screen: PPM 1024, 992 pulses
  EXPECT_EQ(check_ppm_against_weight(992, 992).error, 49);
  EXPECT_EQ(check_ppm_against_weight(100, 992).error, 49);
}

TEST(UlsConformance, U17_MnemonicsAreCaseInsensitive) {  // §8 terminal users
  const FrameView view = must_parse("$mm,1");
  EXPECT_TRUE(view.is("MM"));
  EXPECT_EQ(view.mnemonic, "mm");
  EXPECT_EQ(find_command("mM"), find_command("MM"));
  EXPECT_EQ(wire_of(encode_frame(Address::none(), view.mnemonic, view.fields())), "$MM,1\r");
  EXPECT_EQ(validate_request("mm", view.fields()), Verdict::accept());
}

TEST(UlsConformance, U21_TripTimeoutIsHexPulses) {  // §8 TT "(seconds * 3000) in hexadecimal", §3
  EXPECT_EQ(trip_timeout_pulses(360), 1'080'000U);
  EXPECT_EQ(to_hex_text(1'080'000).view(), "107AC0");
  EXPECT_EQ(to_hex_text(8000).view(), "1F40");
  EXPECT_EQ(parse_trip_timeout("107AC0"), 1'080'000U);
  EXPECT_EQ(parse_trip_timeout("1f40"), 8000U);
  EXPECT_DOUBLE_EQ(trip_timeout_seconds(1'080'000), 360.0);
  const CommandInfo& tt = *find_command("TT");
  const std::array<std::string_view, 1> good{"107AC0"};
  const std::array<std::string_view, 1> nine{"123456789"};
  const std::array<std::string_view, 1> bad{"10G"};
  EXPECT_TRUE(validate_request(tt, good).ok());
  EXPECT_EQ(validate_request(tt, nine).error, 1);
  EXPECT_EQ(validate_request(tt, bad).error, 33);  // not hex: "Invalid Input Base" (U80)
  EXPECT_EQ(wire_of(encode_set(Address::none(), "TT", std::array<std::string_view, 1>{"107AC0"})), "$TT,107AC0\r");
}

TEST(UlsConformance, U25_UnitAddressSetCarriesOneCharacter) {  // §8 Set/Get Unit Address, U5
  const CommandInfo& ua = *find_command("UA");
  const std::array<std::string_view, 1> two{"ZZ"};
  const std::array<std::string_view, 1> slash{"/"};
  const std::array<std::string_view, 1> broadcast{"\xF0"};
  const std::array<std::string_view, 1> highest{"\xEF"};
  EXPECT_EQ(validate_request(ua, two).error, 1);
  EXPECT_EQ(validate_request(ua, slash).error, 1);
  EXPECT_EQ(validate_request(ua, broadcast).error, 1);
  EXPECT_TRUE(validate_request(ua, highest).ok());

  // 0xEF travels through the framer at the value slot only.
  for (const std::string_view wire : {std::string_view("$UA,\xEF\r"), std::string_view("#ZUA,\xEF\r")}) {
    const Result<FrameView> parsed = parse_wire_frame(as_bytes(wire));
    ASSERT_TRUE(parsed.ok()) << parsed.error().describe();
    EXPECT_EQ(parsed->fields()[0], "\xEF");
    EXPECT_EQ(wire_of(encode_frame(parsed->address, parsed->mnemonic, parsed->fields())), wire);
  }
  EXPECT_FALSE(parse_wire_frame(as_bytes("$UA,\xEF\xEF\r")).ok());
  EXPECT_FALSE(parse_wire_frame(as_bytes("$MM,\xEF\r")).ok());
}

TEST(UlsConformance, U26_FourUpperHexDigitsAreAnEvent) {
  EXPECT_EQ(must_parse("$BEEF").kind, FrameKind::time_between_events);
  EXPECT_EQ(must_parse("#ZBEEF").event_text, "BEEF");
  const FrameView lower = must_parse("$beef");
  EXPECT_EQ(lower.kind, FrameKind::message);
  EXPECT_EQ(lower.mnemonic, "beef");
  EXPECT_EQ(must_parse("$BEEF,1").kind, FrameKind::message);
  EXPECT_FALSE(encode_get(Address::none(), "BEEF").ok());
  EXPECT_FALSE(encode_get(Address::none(), "beef").ok());  // written upper case, it would read as an event
  for (const CommandInfo& command : command_table()) {
    EXPECT_NE(parse_frame(std::string("$") + std::string(command.mnemonic)).value().kind,
              FrameKind::time_between_events)
        << command.mnemonic;
  }
}

TEST(UlsConformance, U27_FieldWidthsOfSection9) {  // §9 "12 characters max", "21 characters max", "20 characters max"
  const Address plain = Address::none();
  const Result<FrameText> metres = encode_averaging(plain, {make_range(9999.999, Units::metres), std::nullopt});
  EXPECT_EQ(wire_of(metres), "$BM,9999.999\r");
  EXPECT_EQ(metres->frame().size(), 12U);
  const Result<FrameText> feet = encode_averaging(plain, {make_range(99999.99, Units::feet), std::nullopt});
  EXPECT_EQ(wire_of(feet), "$BM,99999.99\r");
  EXPECT_EQ(feet->frame().size(), 12U);
  const Result<FrameText> negative = encode_averaging(plain, {make_range(-999.999, Units::metres), std::nullopt});
  EXPECT_EQ(wire_of(negative), "$BM,-999.999\r");
  EXPECT_EQ(negative->frame().size(), 12U);
  const Result<FrameText> both = encode_averaging(plain, {make_range(9999.999, Units::metres), 9'999'999U});
  EXPECT_EQ(wire_of(both), "$BM,9999.999,9999999\r");
  EXPECT_EQ(both->wire().size(), 21U);  // with the CR

  EXPECT_FALSE(encode_averaging(plain, {make_range(10000.0, Units::metres), std::nullopt}).ok());
  EXPECT_FALSE(encode_averaging(plain, {make_range(-1000.0, Units::metres), std::nullopt}).ok());
  EXPECT_FALSE(encode_averaging(plain, {std::nullopt, 10'000'000U}).ok());
  EXPECT_FALSE(decode_measurement(as_bytes("$BM,10000.000"), averaging(DisplayMode::range)).ok());
  EXPECT_FALSE(decode_measurement(as_bytes("$BM,1.000,10000000"), averaging(DisplayMode::range_and_intensity)).ok());

  const Result<FrameText> target =
      encode_binning_target(plain, {0, 1, make_range(1664.000, Units::metres), 128});  // §9 single target
  EXPECT_EQ(wire_of(target), "$BM,0,1,1664.000,128\r");
  EXPECT_EQ(target->frame().size(), 20U);
  EXPECT_TRUE(encode_binning_target(plain, {14, 15, make_range(9999.999, Units::metres), 65535}).ok());
  EXPECT_FALSE(encode_binning_target(plain, {0, 1, make_range(1.0, Units::metres), 65536}).ok());
  EXPECT_FALSE(encode_binning_target(plain, {15, 16, make_range(1.0, Units::metres), 1}).ok());
}

TEST(UlsConformance, U29_ReplyShapes) {
  EXPECT_TRUE(decode_reply(as_bytes("$PO,1024,100")).ok());
  EXPECT_FALSE(decode_reply(as_bytes("$PO,1024")).ok());
  EXPECT_TRUE(decode_reply(as_bytes("$BR,1,57600")).ok());
  EXPECT_FALSE(decode_reply(as_bytes("$BR,1,57601")).ok());
  EXPECT_FALSE(decode_reply(as_bytes("$BR,57600")).ok());
  EXPECT_FALSE(decode_reply(as_bytes("$GO,1")).ok());
  EXPECT_FALSE(decode_reply(as_bytes("$PT,1")).ok());
  EXPECT_FALSE(decode_reply(as_bytes("$MM,4")).ok());
  EXPECT_FALSE(decode_reply(as_bytes("$UA,Z")).ok());  // the get reply is decimal
  EXPECT_FALSE(decode_reply(as_bytes("$XX,1")).ok());
  EXPECT_EQ(decode_reply(as_bytes("$XX,1")).error().code, Errc::unknown_command);
  // Distances in the unit's MU: 1700 m is 5577.43 ft.
  EXPECT_TRUE(decode_reply(as_bytes("$LG,5577.42"), Units::feet).ok());
  EXPECT_FALSE(decode_reply(as_bytes("$LG,5577.44"), Units::feet).ok());
}

TEST(UlsConformance, U31_ErrorNumbersOutsideTheTableAreKept) {
  const Result<Reply> two = decode_reply(as_bytes("$ER,2"));
  ASSERT_TRUE(two.ok());
  EXPECT_EQ(two->error_number, 2);
  EXPECT_EQ(two->error, nullptr);
  EXPECT_FALSE(decode_reply(as_bytes("$ER,0")).ok());
  EXPECT_FALSE(decode_reply(as_bytes("$ER,1000")).ok());
  EXPECT_FALSE(decode_reply(as_bytes("$ER")).ok());
  EXPECT_FALSE(decode_reply(as_bytes("$OK,1")).ok());
}

TEST(UlsConformance, U32_DecoderIsStrictAboutContext) {
  const MeasurementContext look_down{Mode::look_down, DisplayMode::range, Units::metres, false};
  EXPECT_FALSE(decode_measurement(as_bytes("$0BB8"), look_down).ok());  // TB off
  EXPECT_FALSE(decode_measurement(as_bytes("$0BB8"), averaging(DisplayMode::range)).ok());
  EXPECT_FALSE(decode_measurement(as_bytes("$BM,1"), events).ok());  // TB on
  EXPECT_FALSE(decode_measurement(as_bytes("#\xF0"
                                           "BM,1"),
                                  look_down)
                   .ok());
  EXPECT_FALSE(decode_measurement(as_bytes("$MM,1"), look_down).ok());
}

}  // namespace
}  // namespace rangekit::uls
