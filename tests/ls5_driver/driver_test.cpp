// The driver's request/reply side against scripted device bytes on the in-memory
// loopback: every table 9.1 command, readable settings, checks before sending,
// reply matching through garbage, half frames and other sensors' replies, retries.
#include <gtest/gtest.h>

#include <thread>

#include "rangekit/ls5/family.hpp"
#include "rangekit/ls5/settings.hpp"
#include "scripted_device.hpp"

using namespace rangekit;
using namespace rangekit::ls5;
using namespace ls5_driver_test;

namespace {

struct Fixture {
  explicit Fixture(DriverOptions options = fast_options()) {
    auto pair = make_loopback_pair("driver", "device");
    device = std::make_unique<ScriptedDevice>(std::move(pair.b));
    driver = std::make_unique<Driver>(std::move(pair.a), options);
  }
  std::unique_ptr<ScriptedDevice> device;
  std::unique_ptr<Driver> driver;
};

DriverOptions with_firmware(FirmwareVersion firmware, std::uint8_t address = 0x01) {
  DriverOptions options = fast_options(address);
  options.assumed_firmware = firmware;
  return options;
}

}  // namespace

TEST(Ls5Driver, IdentifyDecodesTheSection92Example) {
  Fixture f;
  f.device->send(id_reply_01);
  auto id = f.driver->identify();
  ASSERT_TRUE(id) << id.error().message;
  EXPECT_EQ(f.device->receive_until("\r"), "#01ID\r");
  ASSERT_TRUE(id->version.has_value());
  EXPECT_EQ(*id->version, (FirmwareVersion{6, 0}));
  EXPECT_DOUBLE_EQ(id->lower_boundary_mm, 8.1234);
  EXPECT_DOUBLE_EQ(id->range_mm, 40.001);
  EXPECT_EQ(id->serial_number, 157U);
}

TEST(Ls5Driver, SetMedianFilterIsTheSection94Session) {
  Fixture f(with_firmware(firmware_6_0, 0x02));
  f.device->send("!02W0B01\r");  // §9.4: response to #02W0B01
  auto status = f.driver->set("pre-filter", "median");
  ASSERT_TRUE(status) << status.error().message;
  EXPECT_EQ(f.device->receive_until("\r"), "#02W0B01\r");
}

// L55: DF restores table 9.2's network address 01; the echo still comes from the
// old address, the next request must go to 01.
TEST(Ls5Driver, RestoreDefaultsFollowsTheSensorToAddress01L55) {
  Fixture f(with_firmware(firmware_6_0, 0x05));
  f.device->send("!05DF\r");
  ASSERT_TRUE(f.driver->restore_defaults());
  EXPECT_EQ(f.device->receive_until("\r"), "#05DF\r");
  EXPECT_EQ(f.driver->address(), 0x01);
  f.device->send("!01R0B00\r");
  ASSERT_TRUE(f.driver->read_parameter(0x0B));
  EXPECT_EQ(f.device->receive_until("\r"), "#01R0B\r");
}

// U67: an RS-485 adapter that echoes the host's bytes puts `#02W0B01` ahead of
// the reply; requests start with '#', so the reply framer drops it.
TEST(Ls5Driver, OwnRequestEchoedByAnRs485AdapterIsSkipped) {
  Fixture f(with_firmware(firmware_6_0, 0x02));
  f.device->send("#02W0B01\r!02W0B01\r");
  auto status = f.driver->set("pre-filter", "median");
  ASSERT_TRUE(status) << status.error().message;
  f.device->send("#02R0B\r!02R0B01\r");
  auto read = f.driver->read_parameter(0x0B);
  ASSERT_TRUE(read) << read.error().message;
  EXPECT_EQ(*read, 0x01);
}

TEST(Ls5Driver, TurnOnIsTheSection94Session) {
  Fixture f;
  f.device->send("!01ON\r");
  ASSERT_TRUE(f.driver->start_measuring());
  EXPECT_EQ(f.device->receive_until("\r"), "#01ON\r");
}

TEST(Ls5Driver, EveryEchoedCommandSendsItsCode) {
  Fixture f;
  struct Case {
    Status (Driver::*call)();
    const char* code;
  };
  const Case cases[] = {{&Driver::store_to_flash, "FL"},
                        {&Driver::stop_measuring, "OF"},
                        {&Driver::latch, "FX"},
                        {&Driver::stop_stream, "SB"},
                        {&Driver::restore_defaults, "DF"}};
  for (const Case& c : cases) {
    f.device->send(std::string("!01") + c.code + "\r");
    Status status = (f.driver.get()->*c.call)();
    EXPECT_TRUE(status) << c.code << ": " << status.error().message;
    EXPECT_EQ(f.device->receive_until("\r"), std::string("#01") + c.code + "\r");
  }
}

// The deprecated names still compile and send the same command, for existing callers.
TEST(Ls5Driver, DeprecatedTurnOnAndTurnOffStillSendOnAndOf) {
  auto pair = make_loopback_pair();
  ScriptedDevice device(std::move(pair.b));
  Driver driver(std::move(pair.a), fast_options());
  device.send("!01ON\r!01OF\r");  // table 9.1 "Turn on the sensor" / "Turn off the sensor" echoes
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
  EXPECT_TRUE(driver.turn_on());
  EXPECT_TRUE(driver.turn_off());
#pragma GCC diagnostic pop
  EXPECT_EQ(device.receive_until("#01OF\r"), "#01ON\r#01OF\r");
}

TEST(Ls5Driver, SwingsOfTable93AreWrittenLowByteFirst) {
  Fixture f(with_firmware(firmware_6_0));
  // Table 9.3: first swing of output 1 = 20000 (0x4E20): #01W1620, #01W174E.
  f.device->send("!01W1620\r!01W174E\r");
  auto status = f.driver->set("output1-first-swing", "20000");
  ASSERT_TRUE(status) << status.error().message;
  EXPECT_EQ(f.device->receive_until("#01W174E\r"), "#01W1620\r#01W174E\r");
}

TEST(Ls5Driver, GetCombinesBytesAndFormatsUnits) {
  Fixture f(with_firmware(firmware_6_0));
  // Table 9.2: period 0x0034 = 5.2 ms.
  f.device->send("!01R0634\r!01R0700\r");
  auto reading = f.driver->get("period-ms");
  ASSERT_TRUE(reading) << reading.error().message;
  EXPECT_EQ(reading->text, "5.2");
  EXPECT_EQ(f.device->receive_until("#01R07\r"), "#01R06\r#01R07\r");
}

TEST(Ls5Driver, MillimetreSettingsUseTheRangeFromIdentification) {
  Fixture f;
  f.device->send(id_reply_01);
  // Half the 40.001 mm range is code 25000 = 0x61A8 (formula 8.5). High byte first (L62):
  // A8 after a high byte C3 would make 0xC3A8 = 50088 for a moment.
  f.device->send("!01W1261\r!01W11A8\r");
  auto status = f.driver->set("analog-lower-mm", "20.0005");
  ASSERT_TRUE(status) << status.error().message;
  EXPECT_EQ(f.device->receive_until("#01W11A8\r"), "#01ID\r#01W1261\r#01W11A8\r");
}

// docs/conformance.md L40: checked before sending, refusal names the allowed values.
TEST(Ls5Driver, OutOfRangeValuesAreRefusedBeforeAnythingIsSent) {
  Fixture f(with_firmware(firmware_12_x));
  struct Case {
    const char* name;
    const char* value;
    const char* allowed;
  };
  const Case cases[] = {
      {"median-points", "4", "1, 3, ..., 49 (odd)"},  // L4
      {"median-points", "51", "1, 3, ..., 49 (odd)"},
      {"thinning", "0", "1-255"},
      {"analog-upper", "50001", "0-50000"},
      {"period-ms", "0.05", "0.1-6553.5 ms"},  // not a whole number of 0.1 ms (L21)
      {"baud-rate", "14400", "9600 | 19200"},
      {"pre-filter", "mean", "average | median"},
      {"ip-address", "192.168.0", "IPv4"},
  };
  for (const Case& c : cases) {
    Status status = f.driver->set(c.name, c.value);
    ASSERT_FALSE(status) << c.name << "=" << c.value;
    EXPECT_NE(status.error().message.find(c.name), std::string::npos) << status.error().message;
    EXPECT_NE(status.error().message.find(c.allowed), std::string::npos) << status.error().message;
  }
  EXPECT_EQ(f.device->receive_all(), "") << "nothing may reach the sensor";
}

TEST(Ls5Driver, NewerParametersAreRefusedWithTheFirmwareTheyNeed) {
  Fixture f;
  f.device->send(id_reply_01);  // LS5.6.0
  Status exposure = f.driver->set("max-exposure-us", "100");
  ASSERT_FALSE(exposure);
  EXPECT_EQ(exposure.error().code, Errc::unsupported);
  EXPECT_NE(exposure.error().message.find("LS5.7.0"), std::string::npos) << exposure.error().message;
  Status latching = f.driver->set("latching", "analog");  // value 02 needs LS5.9.0 (§8.14)
  ASSERT_FALSE(latching);
  EXPECT_NE(latching.error().message.find("LS5.9.0"), std::string::npos) << latching.error().message;
  auto udp = f.driver->get("udp-auto-stream");
  ASSERT_FALSE(udp);
  EXPECT_EQ(f.device->receive_all(), "#01ID\r") << "only the identification went out";
}

// docs/conformance.md L41: reads retried once, writes never; L40: the no-reply hint.
TEST(Ls5Driver, ReadsAreRetriedOnceThenTimeOutWithAHint) {
  Fixture f;
  auto value = f.driver->read_parameter(0x0D);
  ASSERT_FALSE(value);
  EXPECT_EQ(value.error().code, Errc::timeout);
  for (const char* hint : {"did not answer #01R0D", "port", "baud", "address"}) {
    EXPECT_NE(value.error().message.find(hint), std::string::npos) << value.error().message;
  }
  EXPECT_EQ(f.device->receive_all(), "#01R0D\r#01R0D\r");
}

TEST(Ls5Driver, WritesAreNotRetried) {
  Fixture f(with_firmware(firmware_6_0));
  Status status = f.driver->write_parameter(0x0C, 0x04);
  ASSERT_FALSE(status);
  EXPECT_EQ(status.error().code, Errc::timeout);
  EXPECT_EQ(f.device->receive_all(), "#01W0C04\r");
}

TEST(Ls5Driver, ReplyIsFoundBehindGarbageHalfFramesRecordsAndOtherSensors) {
  Fixture f;
  // Garbage, a half frame cut by a new start (F3), a stream record still in flight,
  // a reply from sensor 02, a reply with bad hex, then the answer.
  f.device->send("\x7fzz!01R0!12345\r!02R0D07\r!01R0DZZ\r!01R0D09\r");
  auto value = f.driver->read_parameter(0x0D);
  ASSERT_TRUE(value) << value.error().message;
  EXPECT_EQ(*value, 0x09);
  EXPECT_GE(f.driver->rejected_frames(), 3U);
  EXPECT_EQ(f.device->receive_all(), "#01R0D\r") << "answered at the first attempt";
}

TEST(Ls5Driver, ReplyForAnotherParameterDoesNotAnswer) {
  Fixture f;
  f.device->send("!01R0C07\r");
  auto value = f.driver->read_parameter(0x0D);
  ASSERT_FALSE(value);
  EXPECT_EQ(value.error().code, Errc::timeout);
}

TEST(Ls5Driver, LastAndLatchedResultsWithSpecialCodes) {
  Fixture f;
  f.device->send(id_reply_01);
  ASSERT_TRUE(f.driver->identify());
  f.device->send("!01LR25000\r");
  auto last = f.driver->read_last();
  ASSERT_TRUE(last) << last.error().message;
  EXPECT_EQ(last->code.value, 25000);
  ASSERT_TRUE(last->distance_mm.has_value());
  EXPECT_DOUBLE_EQ(*last->distance_mm, 40.001 * 25000 / 50000);  // formula 8.1
  f.device->send("!01FR65535\r");                                // §8.9 no signal
  auto latched = f.driver->read_latched();
  ASSERT_TRUE(latched) << latched.error().message;
  EXPECT_EQ(latched->code.kind, CodeKind::no_signal);
  EXPECT_FALSE(latched->distance_mm.has_value());
  EXPECT_EQ(f.device->receive_until("#01FR\r"), "#01ID\r#01LR\r#01FR\r");
  // measure(), the verb of both drivers, is LR on the LS5.
  f.device->send("!01LR12500\r");
  auto measured = f.driver->measure();
  ASSERT_TRUE(measured) << measured.error().message;
  EXPECT_EQ(measured->code.value, 12500);
  EXPECT_EQ(f.device->receive_until("#01LR\r"), "#01LR\r");
}

TEST(Ls5Driver, ClosedLinkIsReportedAsClosed) {
  Fixture f;
  f.device->close();
  auto value = f.driver->read_parameter(0x01);
  ASSERT_FALSE(value);
  EXPECT_EQ(value.error().code, Errc::closed);
}

TEST(Ls5Driver, NetworkAddressChangeMovesTheDriver) {
  Fixture f(with_firmware(firmware_6_0));
  f.device->send("!01W0105\r");  // L28: echoed from the old address
  ASSERT_TRUE(f.driver->set("network-address", "5"));
  EXPECT_EQ(f.driver->address(), 5);
  f.device->send("!05R0105\r");
  auto value = f.driver->read_parameter(0x01);
  ASSERT_TRUE(value) << value.error().message;
  EXPECT_EQ(f.device->receive_until("#05R01\r"), "#01W0105\r#05R01\r");
}

// docs/conformance.md L42
TEST(Ls5Driver, InfoAsksR70OnLs512ToLearnAboutEthernet) {
  Fixture f;
  f.device->send("%01LS5.12.0  b0,0000d100,000s/n0000157\r!01R7001\r");
  auto info = f.driver->info();
  ASSERT_TRUE(info) << info.error().message;
  EXPECT_TRUE(info->ethernet);
  EXPECT_DOUBLE_EQ(info->identification.range_mm, 100.0);
  EXPECT_EQ(f.device->receive_until("#01R70\r"), "#01ID\r#01R70\r");
}

// docs/conformance.md L44
TEST(Ls5Driver, ProbeReportsAStreamWithoutSpeakingAndIdentifiesOtherwise) {
  auto pair = make_loopback_pair();
  ScriptedDevice device(std::move(pair.b));
  device.send("!25000\r!25001\r");
  auto streaming = probe(*pair.a, 0x01, 400ms);
  ASSERT_TRUE(streaming) << streaming.error().message;
  EXPECT_TRUE(streaming->streaming);
  EXPECT_EQ(device.receive_all(), "") << "a byte would have stopped the stream (L37)";

  // The sensor answers the ID only after it was asked.
  std::thread sensor([&device] {
    if (device.receive_until("#01ID\r") == "#01ID\r") device.send(id_reply_01);
  });
  auto identified = probe(*pair.a, 0x01, 2000ms);
  sensor.join();
  ASSERT_TRUE(identified) << identified.error().message;
  EXPECT_FALSE(identified->streaming);
  ASSERT_TRUE(identified->identification.has_value());
  EXPECT_EQ(identified->identification->serial_number, 157U);

  auto silent = probe(*pair.a, 0x03, 200ms);
  ASSERT_FALSE(silent);
  EXPECT_EQ(silent.error().code, Errc::timeout);
}

TEST(Ls5Driver, EveryMalformedReplyOfTheCodecCorpusIsSkippedAndCounted) {
  const std::string id_field = "LS5.6.0   b8,1234d40,0010s/n0000157";  // §9.2 example
  // The reply cases of tests/ls5/malformed_test.cpp, each followed by the real answer.
  const std::vector<std::string> bad_replies = {
      "!50001\r",
      "!65533\r",
      "!2500\r",
      "!01FR2500\r",
      "!01FR250000\r",
      "!01FR25A00\r",
      "!01LR50001\r",
      "!01R05\r",
      "!01R05G5\r",
      "!01ID\r",
      "!01ST\r",
      "!00ON\r",
      "!01ZZ\r",
      "!0\r",
      "!A\r",
      "!\r",
      "!01ON\n",
      std::string("!01\0ON\r", 7),
      "%01" + id_field.substr(0, 34) + "\r",
      "%01" + id_field + "0\r",
      "%01" + id_field.substr(0, 28) + "00001x7\r",
      "%01          " + id_field.substr(10) + "\r",
      "%00" + id_field + "\r",
      "%G0" + id_field + "\r",
      "#01ON\r",
  };
  Fixture f;
  for (const std::string& bad : bad_replies) {
    const std::uint64_t rejected_before = f.driver->rejected_frames();
    f.device->send(bad);
    f.device->send("!01R0D05\r");
    auto value = f.driver->read_parameter(0x0D);
    ASSERT_TRUE(value) << testing::PrintToString(bad) << ": " << value.error().message;
    EXPECT_EQ(*value, 0x05) << testing::PrintToString(bad);
    EXPECT_GT(f.driver->rejected_frames(), rejected_before) << testing::PrintToString(bad);
    EXPECT_EQ(f.device->receive_until("\r"), "#01R0D\r") << "answered at the first attempt";
  }
}

// docs/conformance.md L60. §8.9: "if the parameter «Type of preliminary result» equals
// 0x01 (the result is issued as a derivative of the distance) ... distance derivate =
// range · (code − 25000) / 50000 (8.2)". Code 25050 on a 100 mm sensor is +0.1 mm, not
// the 50.1 mm formula 8.1 would give.
TEST(Ls5Driver, DerivativeResultFollowsFormula82NotTheDistanceFormulaL60) {
  Fixture f;
  f.device->send("%01LS5.8.0   b0,0000d100,000s/n0000157\r");  // 0E exists from LS5.8.0 (§8.8 footnote)
  ASSERT_TRUE(f.driver->identify());
  f.device->send("!01R0E01\r!01LR25050\r");
  auto last = f.driver->read_last();
  ASSERT_TRUE(last) << last.error().message;
  EXPECT_EQ(last->code.value, 25050);
  EXPECT_FALSE(last->distance_mm.has_value()) << "a derivative is not a distance: " << last->distance_mm.value_or(0);
  EXPECT_TRUE(last->derivative);
  EXPECT_DOUBLE_EQ(last->derivative_mm.value_or(-1), 0.1);  // 100 × (25050 − 25000) / 50000
  EXPECT_EQ(f.device->receive_until("#01LR\r"), "#01ID\r#01R0E\r#01LR\r");
}

// docs/conformance.md L61 (and the host half of L18). §8.10: "The values of the lower
// and upper bounds can only be in the range 0÷50000." Byte 13 = FF with 14 = C3 on the sensor makes 0xC3FF = 50175:
// the other byte is read first and the write is refused before it is sent.
TEST(Ls5Driver, RawByteWriteIsCheckedWithTheOtherByteAsTheSensorHoldsItL61) {
  Fixture f(with_firmware(firmware_6_0));
  f.device->send("!01R14C3\r");
  Status status = f.driver->write_parameter(0x13, 0xFF);
  ASSERT_FALSE(status);
  EXPECT_EQ(status.error().code, Errc::out_of_range) << status.error().message;
  EXPECT_NE(status.error().message.find("50175"), std::string::npos) << status.error().message;
  EXPECT_NE(status.error().message.find("0-50000"), std::string::npos) << status.error().message;
  EXPECT_EQ(f.device->receive_all(), "#01R14\r") << "only the read went out";

  // With 14 = 00 on the sensor the same byte makes 0x00FF = 255: written.
  f.device->send("!01R1400\r!01W13FF\r");
  ASSERT_TRUE(f.driver->write_parameter(0x13, 0xFF));
  EXPECT_EQ(f.device->receive_until("#01W13FF\r"), "#01R14\r#01W13FF\r");
}

// docs/conformance.md L84. Table 9.3 writes a value low byte first ("#01W1350<cr>
// #01W14C3<cr>" for 50000); §8.10 "The values of the lower and upper bounds can only be in the
// range 0÷50000" holds for the value the pair makes. From 50000, 25000 (0x61A8) given in table
// 9.3's order or the reverse is one value, checked as such and sent in L62's order; a byte alone
// that leaves the value out of range is refused, saying to give its other byte with it.
TEST(Ls5Driver, Table93OrderAndTheReverseAreOneValueCheckedAsAPairL84) {
  Fixture f(with_firmware(firmware_6_0));
  const ParameterWrite table_order[] = {{0x13, 0xA8}, {0x14, 0x61}};
  f.device->send("!01W1461\r!01W13A8\r");
  Status low_first = f.driver->write_parameters(table_order);
  ASSERT_TRUE(low_first) << low_first.error().message;
  EXPECT_EQ(f.device->receive_until("#01W13A8\r"), "#01W1461\r#01W13A8\r");
  const ParameterWrite reverse_order[] = {{0x14, 0x61}, {0x13, 0xA8}};
  f.device->send("!01W1461\r!01W13A8\r");
  Status high_first = f.driver->write_parameters(reverse_order);
  ASSERT_TRUE(high_first) << high_first.error().message;
  EXPECT_EQ(f.device->receive_until("#01W13A8\r"), "#01W1461\r#01W13A8\r");

  f.device->send("!01R14C3\r");  // the sensor holds 14 = C3: 13 = A8 alone makes 0xC3A8 = 50088
  Status half = f.driver->write_parameter(0x13, 0xA8);
  ASSERT_FALSE(half);
  EXPECT_NE(half.error().message.find("50088"), std::string::npos) << half.error().message;
  EXPECT_NE(half.error().message.find("same command (14=..)"), std::string::npos) << half.error().message;
  EXPECT_EQ(f.device->receive_all(), "#01R14\r") << "only the read went out";
}

// docs/conformance.md L62. §8.10/§8.11 limit every combined value to 0-50000, and the
// bytes go out one at a time (§9.3), so the order must keep each step valid: 255
// (0x00FF) after the default 50000 (0xC350) goes high byte first (0xC3FF = 50175 in
// between otherwise); table 9.3's 0xC350 stays low byte first; a period of 25.6 ms
// (0x0100, "0001-FFFF") goes high byte first so that it never passes through 0x0000.
TEST(Ls5Driver, MultiByteWritesKeepEveryIntermediateValueValidL62) {
  Fixture f(with_firmware(firmware_6_0));
  f.device->send("!01W1400\r!01W13FF\r");
  Status low = f.driver->set("analog-upper", "255");
  ASSERT_TRUE(low) << low.error().message;
  EXPECT_EQ(f.device->receive_until("#01W13FF\r"), "#01W1400\r#01W13FF\r");

  f.device->send("!01W1350\r!01W14C3\r");  // table 9.3: #01W1350, #01W14C3
  Status full = f.driver->set("analog-upper", "50000");
  ASSERT_TRUE(full) << full.error().message;
  EXPECT_EQ(f.device->receive_until("#01W14C3\r"), "#01W1350\r#01W14C3\r");

  f.device->send("!01W0701\r!01W0600\r");
  Status period = f.driver->set("period-ms", "25.6");
  ASSERT_TRUE(period) << period.error().message;
  EXPECT_EQ(f.device->receive_until("#01W0600\r"), "#01W0701\r#01W0600\r");
}

// docs/conformance.md L64. Table 9.2, destination port: "For the parameter itself:
// 0001-FFFF", so 1024 (0x0400, low byte 00) is a port the sensor can be given; port 0
// is not. (The table's byte check for 6D is the codec's; see L18.)
TEST(Ls5Driver, DestinationPort1024IsWrittenAndPortZeroRefusedL64) {
  Fixture f(with_firmware(firmware_12_x));
  f.device->send("!01W6C04\r!01W6D00\r");
  Status port = f.driver->set("destination-port", "1024");
  ASSERT_TRUE(port) << port.error().message;
  EXPECT_EQ(f.device->receive_until("#01W6D00\r"), "#01W6C04\r#01W6D00\r");

  f.device->send("!01R6C00\r");  // high byte 00 on the sensor: 6D = 00 would make port 0
  Status zero = f.driver->write_parameter(0x6D, 0x00);
  ASSERT_FALSE(zero);
  EXPECT_EQ(f.device->receive_all(), "#01R6C\r") << "only the read went out";
}

// docs/conformance.md L67. Table 9.1 note 1: "A broadcast request is supported (send a
// command to address 0)"; note 2: "No response in the case of a broadcast request".
// Nothing can be read at 00 (no ID, no R), so the write goes out unasked and unechoed.
TEST(Ls5Driver, BroadcastWritesGoOutWithoutIdentificationOrEchoL67) {
  Fixture f(fast_options(0x00));
  Status median = f.driver->set("pre-filter", "median");
  ASSERT_TRUE(median) << median.error().message;
  Status on = f.driver->start_measuring();
  ASSERT_TRUE(on) << on.error().message;
  EXPECT_EQ(f.device->receive_until("#00ON\r"), "#00W0B01\r#00ON\r");

  // The sensors' other byte of a code cannot be read at 00 (L61): it must be given.
  Status half = f.driver->write_parameter(0x13, 0xFF);
  ASSERT_FALSE(half);
  EXPECT_EQ(half.error().code, Errc::wrong_form) << half.error().message;
  const ParameterWrite both[] = {{0x13, 0xFF}, {0x14, 0x00}};
  ASSERT_TRUE(f.driver->write_parameters(both));
  EXPECT_EQ(f.device->receive_until("#00W13FF\r"), "#00W1400\r#00W13FF\r") << "high byte first (L62)";
  // No range without ID: the mm forms cannot be converted.
  EXPECT_FALSE(f.driver->set("analog-lower-mm", "1"));
  EXPECT_EQ(f.device->receive_all(), "");
}

// docs/conformance.md L63. Table 3.1, discreteness: "up to 10 mm inclusive 0.0001",
// "over 10 to 100 inclusive 0.001", "over 100 to 1000 inclusive 0.01", "more than 1000
// mm 0.1"; the serial stream's samples carry it from the ID range.
TEST(Ls5Driver, DiscretenessFollowsTable31L63) {
  EXPECT_DOUBLE_EQ(discreteness_mm(5), 0.0001);  // table 5.1 LS5-0.5/5: 0.0001
  EXPECT_DOUBLE_EQ(discreteness_mm(10), 0.0001);
  EXPECT_DOUBLE_EQ(discreteness_mm(15), 0.001);  // LS5-2/15: 0.001
  EXPECT_DOUBLE_EQ(discreteness_mm(100), 0.001);
  EXPECT_DOUBLE_EQ(discreteness_mm(200), 0.01);  // LS5-100/200: 0.01
  EXPECT_DOUBLE_EQ(discreteness_mm(1000), 0.01);
  EXPECT_DOUBLE_EQ(discreteness_mm(2000), 0.1);
  const Sample sample = make_ls5_sample(ResultCode{21124, CodeKind::result}, 5.0, "line", 1);
  EXPECT_EQ(sample.get(ls5::channel::resolution_mm), 0.0001);
  EXPECT_DOUBLE_EQ(sample.get(ls5::channel::distance_mm).value_or(-1), 2.1124);  // 5 × 21124 / 50000 (formula 8.1)
  const Sample derivative = make_ls5_sample(ResultCode{24950, CodeKind::result}, 100.0, "line", 1, true);
  EXPECT_EQ(derivative.kind, ls5::kind::derivative);
  EXPECT_FALSE(derivative.get(ls5::channel::distance_mm).has_value());
  EXPECT_DOUBLE_EQ(derivative.get(ls5::channel::derivative_mm).value_or(0),
                   -0.1);  // 100 × (24950 − 25000) / 50000 (8.2, L60)
}
