// Golden lines for hand-built samples: every expected line below is typed by
// hand from the field list in docs/capture.md, not produced by the code.
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <utility>

#include "rangekit/ls5/family.hpp"
#include "rangekit/record/format.hpp"
#include "rangekit/uls/family.hpp"
#include "record/fake_source.hpp"

namespace rangekit::record {
namespace {

using namespace testing;

template <class T>
std::string jsonl(const T& item) {
  std::string out;
  append_jsonl(out, item);
  return out;
}
std::string csv(const Sample& sample) {
  std::string out;
  append_csv(out, sample);
  return out;
}
template <class T>
std::string text(const T& item) {
  std::string out;
  append_text(out, item);
  return out;
}

TEST(IsoTime, UtcWithMillisecondsTruncated) {
  std::string out;
  append_iso_time(out, at() + std::chrono::microseconds(999));
  EXPECT_EQ(out, "2026-11-26T01:02:03.456Z");
  out.clear();
  append_iso_time(out, std::chrono::system_clock::time_point{});
  EXPECT_EQ(out, "1970-01-01T00:00:00.000Z");
}

TEST(Jsonl, UlsAveraging) {
  EXPECT_EQ(jsonl(uls_averaging()),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"uls\",\"address\":3,\"source\":\"/dev/ttyUSB0\","
            "\"kind\":\"averaging\",\"distance_m\":12.3450,\"pulse_width_ns\":18.000}\n");
}

// U92: the key says the unit, and the value is that unit: the wire's integer picoseconds
// (§9 "pico seconds") as nanoseconds (§8 "p = received pulse width in nanoseconds"), exact.
TEST(Jsonl, U92_PulseWidthIsNanosecondsInAKeyThatSaysSo) {
  auto sample = uls_averaging();
  for (const auto& [picoseconds, nanoseconds] :
       {std::pair{33238U, "33.238"}, std::pair{1U, "0.001"}, std::pair{0U, "0.000"}, std::pair{9999999U, "9999.999"}}) {
    sample.set(uls::channel::pulse_width_ps, picoseconds);
    EXPECT_EQ(jsonl(sample),
              "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"uls\",\"address\":3,\"source\":\"/dev/ttyUSB0\","
              "\"kind\":\"averaging\",\"distance_m\":12.3450,\"pulse_width_ns\":" +
                  std::string(nanoseconds) + "}\n");
    EXPECT_EQ(csv(sample), "2026-11-26T01:02:03.456Z,uls,3,/dev/ttyUSB0,averaging,12.3450," + std::string(nanoseconds) +
                               ",,,,,,,,,,,false,\n");
    EXPECT_EQ(text(sample), "01:02:03.456 uls 0x03  12.345 m  pw " + std::string(nanoseconds) + " ns\n");
  }
}

TEST(Jsonl, UlsAveragingWithoutPulseWidthIsNull) {
  auto sample = uls_averaging();
  sample.set(uls::channel::pulse_width_ps, std::nullopt);
  EXPECT_EQ(jsonl(sample),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"uls\",\"address\":3,\"source\":\"/dev/ttyUSB0\","
            "\"kind\":\"averaging\",\"distance_m\":12.3450,\"pulse_width_ns\":null}\n");
}

TEST(Jsonl, NotANumberIsNull) {
  auto sample = uls_averaging();
  sample.set(uls::channel::distance_m, std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(jsonl(sample),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"uls\",\"address\":3,\"source\":\"/dev/ttyUSB0\","
            "\"kind\":\"averaging\",\"distance_m\":null,\"pulse_width_ns\":18.000}\n");
}

TEST(Jsonl, UlsBinningWithoutAddress) {
  EXPECT_EQ(jsonl(uls_binning()),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"uls\",\"address\":null,\"source\":\"/dev/ttyUSB0\","
            "\"kind\":\"binning\",\"targets\":[{\"distance_m\":4.5720,\"strength\":42},"
            "{\"distance_m\":7.1000,\"strength\":13}]}\n");
}

TEST(Jsonl, UlsLookDown) {
  EXPECT_EQ(jsonl(uls_look_down()),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"uls\",\"address\":0,\"source\":\"/dev/ttyUSB1\","
            "\"kind\":\"look-down\",\"presence\":true,\"pulses_between_events\":250,\"pulses_overflow\":false}\n");
}

// U88: `$0000` reads as more than 65535 pulses, never as 0.
TEST(Jsonl, U88_UlsLookDownOverflowIsMoreThan65535PulsesNotZero) {
  EXPECT_EQ(jsonl(uls_look_down_overflow()),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"uls\",\"address\":0,\"source\":\"/dev/ttyUSB1\","
            "\"kind\":\"look-down\",\"presence\":true,\"pulses_between_events\":null,\"pulses_overflow\":true}\n");
  EXPECT_EQ(csv(uls_look_down_overflow()),
            "2026-11-26T01:02:03.456Z,uls,0,/dev/ttyUSB1,look-down,,,,true,,true,,,,,,,false,\n");
  EXPECT_EQ(text(uls_look_down_overflow()), "01:02:03.456 uls 0x00  present  pulses >65535\n");
}

TEST(Jsonl, UlsError) {
  EXPECT_EQ(jsonl(uls_error()),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"uls\",\"address\":3,\"source\":\"/dev/ttyUSB0\","
            "\"kind\":\"error\",\"error\":4,\"error_text\":\"Lock Not Found (display: Target Not Found)\"}\n");
}

TEST(Jsonl, Ls5DistanceAndNoSignal) {
  EXPECT_EQ(jsonl(ls5_result(12345, 1234.5, ls5::SignalState::ok)),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"ls5\",\"address\":null,"
            "\"source\":\"udp:127.0.0.1:5000\",\"kind\":\"result\",\"code\":12345,\"distance_mm\":1234.50,"
            "\"signal\":\"ok\"}\n");
  EXPECT_EQ(jsonl(ls5_result(65535, std::nullopt, ls5::SignalState::lost)),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"ls5\",\"address\":null,"
            "\"source\":\"udp:127.0.0.1:5000\",\"kind\":\"result\",\"code\":65535,\"distance_mm\":null,"
            "\"signal\":\"lost\"}\n");
  EXPECT_EQ(jsonl(ls5_result(65534, std::nullopt, ls5::SignalState::none_yet)),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"ls5\",\"address\":null,"
            "\"source\":\"udp:127.0.0.1:5000\",\"kind\":\"result\",\"code\":65534,\"distance_mm\":null,"
            "\"signal\":\"none_yet\"}\n");
}

TEST(Jsonl, EventsAndEscapedStrings) {
  EXPECT_EQ(jsonl(event(StreamEventKind::lost_records, "UDP counter gap", 3)),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"event\":\"lost_records\",\"message\":\"UDP counter gap\","
            "\"count\":3}\n");
  EXPECT_EQ(jsonl(event(StreamEventKind::bad_frame, "got \"$BM\\x\"\n\x01")),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"event\":\"bad_frame\",\"message\":"
            "\"got \\\"$BM\\\\x\\\"\\n\\u0001\",\"count\":0}\n");
}

// The families' channels in registration order: the ULS's, then the LS5's.
TEST(Csv, HeaderNamesTheJsonKeys) {
  EXPECT_EQ(csv_header(),
            "time,device,address,source,kind,distance_m,pulse_width_ns,targets,presence,pulses_between_events,"
            "pulses_overflow,error,code,distance_mm,signal,derivative_mm,error_text,suspect,suspect_reason\n");
}

TEST(Csv, OneRowPerFamily) {
  EXPECT_EQ(csv(uls_averaging()),
            "2026-11-26T01:02:03.456Z,uls,3,/dev/ttyUSB0,averaging,12.3450,18.000,,,,,,,,,,,false,\n");
  EXPECT_EQ(csv(uls_binning()),
            "2026-11-26T01:02:03.456Z,uls,,/dev/ttyUSB0,binning,,,4.5720:42;7.1000:13,,,,,,,,,,false,\n");
  EXPECT_EQ(csv(uls_look_down()),
            "2026-11-26T01:02:03.456Z,uls,0,/dev/ttyUSB1,look-down,,,,true,250,false,,,,,,,false,\n");
  EXPECT_EQ(csv(uls_error()),
            "2026-11-26T01:02:03.456Z,uls,3,/dev/ttyUSB0,error,,,,,,,4,,,,,Lock Not Found (display: Target Not "
            "Found),false,\n");
  EXPECT_EQ(csv(ls5_result(12345, 1234.5, ls5::SignalState::ok)),
            "2026-11-26T01:02:03.456Z,ls5,,udp:127.0.0.1:5000,result,,,,,,,,12345,1234.50,ok,,,false,\n");
  EXPECT_EQ(csv(ls5_result(65535, std::nullopt, ls5::SignalState::lost)),
            "2026-11-26T01:02:03.456Z,ls5,,udp:127.0.0.1:5000,result,,,,,,,,65535,,lost,,,false,\n");
}

TEST(Csv, QuotesFieldsWithCommasOrQuotes) {
  auto sample = uls_averaging();
  sample.source = "a,\"b\"";
  EXPECT_EQ(csv(sample), "2026-11-26T01:02:03.456Z,uls,3,\"a,\"\"b\"\"\",averaging,12.3450,18.000,,,,,,,,,,,false,\n");
}

TEST(Text, ReadableLinePerFamily) {
  // U92: the pulse width with its unit (ps on the wire, U8, shown in ns).
  EXPECT_EQ(text(uls_averaging()), "01:02:03.456 uls 0x03  12.345 m  pw 18.000 ns\n");
  EXPECT_EQ(text(uls_binning()), "01:02:03.456 uls  4.572 m (42)  7.100 m (13)\n");
  EXPECT_EQ(text(uls_look_down()), "01:02:03.456 uls 0x00  present  pulses 250\n");
  // U90: §10 "4 | Lock Not Found | Target Not Found", not a bare number.
  EXPECT_EQ(text(uls_error()), "01:02:03.456 uls 0x03  error 4: Lock Not Found (display: Target Not Found)\n");
  EXPECT_EQ(text(ls5_result(12345, 1234.5, ls5::SignalState::ok)), "01:02:03.456 ls5  1234.50 mm  code 12345\n");
  EXPECT_EQ(text(ls5_result(65535, std::nullopt, ls5::SignalState::lost)), "01:02:03.456 ls5  no signal  code 65535\n");
  EXPECT_EQ(text(ls5_result(65534, std::nullopt, ls5::SignalState::none_yet)),
            "01:02:03.456 ls5  no measurement yet  code 65534\n");
}

// docs/cli.md "One vocabulary": a person reads a unit address as its family writes it, a ULS
// unit's as the §8 UA table's character ('A', not 65) or in hex where there is none; an LS5
// network address in decimal. The machine formats keep the byte on the wire.
TEST(Text, TheAddressIsSpeltAsItsFamilyWritesIt) {
  auto bus_unit = uls_averaging();
  bus_unit.address = 'A';
  EXPECT_EQ(text(bus_unit), "01:02:03.456 uls A  12.345 m  pw 18.000 ns\n");
  EXPECT_EQ(csv(bus_unit), "2026-11-26T01:02:03.456Z,uls,65,/dev/ttyUSB0,averaging,12.3450,18.000,,,,,,,,,,,false,\n");
  EXPECT_NE(jsonl(bus_unit).find("\"address\":65,"), std::string::npos);
  bus_unit.address = 0x9C;  // §8 RS485 Protocol: 0x30-0xEF, beyond what a terminal shows
  EXPECT_EQ(text(bus_unit), "01:02:03.456 uls 0x9C  12.345 m  pw 18.000 ns\n");
  auto networked = ls5_result(12345, 1234.5, ls5::SignalState::ok);
  networked.address = 26;
  EXPECT_EQ(text(networked), "01:02:03.456 ls5 26  1234.50 mm  code 12345\n");
}

// docs/conformance.md L63. Table 3.1: discreteness "up to 10 mm inclusive 0.0001",
// "over 10 to 100 inclusive 0.001", "over 100 to 1000 inclusive 0.01", "more than 1000
// mm 0.1". Table 5.1: LS5-0.5/5 has 0.0001; code 21124 is 5 × 21124 / 50000 = 2.1124 mm.
TEST(Ls5Precision, TheSensorsDiscretenessDecidesTheDecimalsL63) {
  auto fine = ls5_result(21124, 2.1124, ls5::SignalState::ok);
  fine.set(ls5::channel::resolution_mm, 0.0001);
  EXPECT_EQ(jsonl(fine),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"ls5\",\"address\":null,"
            "\"source\":\"udp:127.0.0.1:5000\",\"kind\":\"result\",\"code\":21124,\"distance_mm\":2.1124,"
            "\"signal\":\"ok\"}\n");
  EXPECT_EQ(csv(fine), "2026-11-26T01:02:03.456Z,ls5,,udp:127.0.0.1:5000,result,,,,,,,,21124,2.1124,ok,,,false,\n");
  EXPECT_EQ(text(fine), "01:02:03.456 ls5  2.1124 mm  code 21124\n");

  // A 40 mm range: 0.001 (15432 of 50000 is 12.3456 mm); a 2000 mm range: 0.1 (20000 of 50000 is 800 mm).
  auto middle = ls5_result(15432, 12.3456, ls5::SignalState::ok);
  middle.set(ls5::channel::resolution_mm, 0.001);
  EXPECT_EQ(text(middle), "01:02:03.456 ls5  12.346 mm  code 15432\n");
  auto coarse = ls5_result(20000, 800.0, ls5::SignalState::ok);
  coarse.set(ls5::channel::resolution_mm, 0.1);
  EXPECT_EQ(text(coarse), "01:02:03.456 ls5  800.0 mm  code 20000\n");
}

// docs/conformance.md L60. §8.9 formula 8.2: with «Type of preliminary result» = 0x01
// the code is a derivative: 25050 on a 100 mm sensor is +0.1 mm, 24950 is -0.1 mm.
TEST(Ls5Derivative, IsItsOwnKindWithDerivativeMmL60) {
  auto rising = ls5_result(25050, std::nullopt, ls5::SignalState::ok);
  rising.kind = ls5::kind::derivative;
  rising.set(ls5::channel::derivative_mm, 0.1);
  rising.set(ls5::channel::resolution_mm, 0.001);
  EXPECT_EQ(jsonl(rising),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"ls5\",\"address\":null,"
            "\"source\":\"udp:127.0.0.1:5000\",\"kind\":\"derivative\",\"code\":25050,\"derivative_mm\":0.100,"
            "\"signal\":\"ok\"}\n");
  EXPECT_EQ(csv(rising),
            "2026-11-26T01:02:03.456Z,ls5,,udp:127.0.0.1:5000,derivative,,,,,,,,25050,,ok,0.100,,false,\n");
  EXPECT_EQ(text(rising), "01:02:03.456 ls5  derivative +0.100 mm  code 25050\n");
  auto falling = rising;
  falling.set(ls5::channel::code, 24950);
  falling.set(ls5::channel::derivative_mm, -0.1);
  EXPECT_EQ(text(falling), "01:02:03.456 ls5  derivative -0.100 mm  code 24950\n");
  auto lost = ls5_result(65535, std::nullopt, ls5::SignalState::lost);
  lost.kind = ls5::kind::derivative;
  EXPECT_EQ(text(lost), "01:02:03.456 ls5  derivative  no signal  code 65535\n");
}

TEST(Text, Events) {
  EXPECT_EQ(text(event(StreamEventKind::disconnected, "/dev/ttyUSB0 went away")),
            "01:02:03.456 disconnected: /dev/ttyUSB0 went away\n");
  EXPECT_EQ(text(event(StreamEventKind::lost_records, "UDP counter gap", 3)),
            "01:02:03.456 lost_records: UDP counter gap (3 lost)\n");
  // The ULS stream's switch to polling is shown, not silent.
  EXPECT_EQ(text(event(StreamEventKind::polling, "/dev/ttyUSB0: polling with BM every 50 ms")),
            "01:02:03.456 polling: /dev/ttyUSB0: polling with BM every 50 ms\n");
  EXPECT_EQ(jsonl(event(StreamEventKind::polling, "p")),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"event\":\"polling\",\"message\":\"p\",\"count\":0}\n");
}

// U102/L71: a suspect sample keeps its value and says so in every format.
TEST(Formats, U102_L71_ASuspectSampleIsMarkedWithItsReason) {
  auto sample = ls5_result(34845, 696.9, ls5::SignalState::ok);
  sample.suspect = true;
  sample.suspect_reason = "jump: 0.6969 m";
  EXPECT_EQ(jsonl(sample),
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"ls5\",\"address\":null,"
            "\"source\":\"udp:127.0.0.1:5000\",\"kind\":\"result\",\"code\":34845,\"distance_mm\":696.90,"
            "\"signal\":\"ok\",\"suspect\":true,\"suspect_reason\":\"jump: 0.6969 m\"}\n");
  EXPECT_EQ(csv(sample),
            "2026-11-26T01:02:03.456Z,ls5,,udp:127.0.0.1:5000,result,,,,,,,,34845,696.90,ok,,,true,jump: 0.6969 m\n");
  EXPECT_EQ(text(sample), "01:02:03.456 ls5  696.90 mm  code 34845  SUSPECT: jump: 0.6969 m\n");
}

}  // namespace
}  // namespace rangekit::record
