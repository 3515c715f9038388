// Formulas and tables: output rate (§2, §9), serial pacing (U19), bin sizes
// (§8, §9, U20, U33), 4-20 mA (§6, U23), look down and events (§3, U34).
// Expected figures are the document's, typed by hand.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "rangekit/uls/uls.hpp"

namespace rangekit::uls {
namespace {

TEST(UlsTiming, OutputRateIsPrfOverPpm) {
  EXPECT_DOUBLE_EQ(output_period_s(1024, 2000), 0.512);  // §2 "a measurement every 512 ms"
  EXPECT_DOUBLE_EQ(output_rate_hz(3000, 300), 10.0);     // §9 averaging "3000/300 Hz or 10 Hz"
  EXPECT_DOUBLE_EQ(output_rate_hz(1000, 100), 10.0);     // §9 binning "1000/100 Hz or 10 Hz"
  EXPECT_DOUBLE_EQ(output_rate_hz(1000, 25), 40.0);      // §9 binning "1000/25 or 40 Hz"
  EXPECT_DOUBLE_EQ(output_period_s(300, 3000), 0.1);
}

TEST(UlsConformance, U19_CharacterTimeScalesWithBaud) {        // §9 Output Data Rate
  EXPECT_DOUBLE_EQ(character_time_s(115200), 100e-6);          // "approximately 100 µs per character at 115200"
  EXPECT_DOUBLE_EQ(character_time_s(57600), 200e-6);           // "will double to 200 µs at ... 57600"
  EXPECT_NEAR(line_time_s(12, 115200), 1.2e-3, 1e-12);         // "12 characters x 100 µs = 1.2 ms"
  EXPECT_EQ(std::floor(max_line_rate_hz(12, 115200)), 833.0);  // "1/1.2 ms = 833 Hz"
  EXPECT_NEAR(line_time_s(21, 115200), 2.1e-3, 1e-12);         // "21 characters x 100 µs = 2.1 ms"
  EXPECT_EQ(std::floor(max_line_rate_hz(21, 115200)), 476.0);  // "1/2.1 ms = 476 Hz"
  EXPECT_NEAR(line_time_s(300, 115200), 30e-3, 1e-12);         // binning "20 x 15 = 300 characters ... 30 ms"
  EXPECT_EQ(std::floor(max_line_rate_hz(300, 115200)), 33.0);  // "33 Hz"
}

TEST(UlsTiming, BaudChoicesOfSection9) {  // §9 Communications "Baud Rate Choices"
  const std::array<std::uint32_t, 10> printed{1200, 2400, 4800, 9600, 14400, 19200, 38400, 57600, 115200, 230400};
  const auto choices = baud_choices();
  ASSERT_EQ(choices.size(), printed.size());
  for (std::size_t i = 0; i < printed.size(); ++i) EXPECT_EQ(choices[i], printed[i]);
  EXPECT_FALSE(is_baud_choice(300));
  EXPECT_FALSE(is_baud_choice(460800));
  EXPECT_EQ(interface_program_max_baud, 115200U);  // "Interface Program Maximum Baud Rate: 115200"
  EXPECT_EQ(serial_command_max_baud, 230400U);     // "Serial Command Maximum Baud Rate: 230400"
}

// §8 Set/Get Bin Size n -> inches; §9 Binning Mode "± a cm typical at b m max. range".
struct BinRow {
  int n;
  std::uint32_t inches;
  double accuracy_cm;
  std::uint32_t max_range_m;
};
constexpr std::array<BinRow, 9> printed_bins{{
    {0, 1, 2.5, 13},
    {1, 2, 5.1, 26},
    {2, 4, 10.2, 52},
    {3, 8, 20.4, 104},
    {4, 16, 40.8, 208},
    {5, 32, 81.6, 416},
    {6, 64, 163.2, 832},
    {7, 128, 326.4, 1664},
    {8, 256, 652.8, 3329},  // n = 8 by U20's rule
}};

TEST(UlsConformance, U20_BinSizeTable) {
  const auto table = bin_size_table();
  ASSERT_EQ(table.size(), 9U);
  for (const BinRow& row : printed_bins) {
    SCOPED_TRACE(row.n);
    const auto size = *to_bin_size(static_cast<std::uint64_t>(row.n));
    const BinSizeInfo& info = bin_size_info(size);
    EXPECT_EQ(info.inches, row.inches);
    EXPECT_DOUBLE_EQ(info.accuracy_cm, row.accuracy_cm);
    EXPECT_EQ(info.max_range_m, row.max_range_m);
    EXPECT_DOUBLE_EQ(bin_size_m(size), row.inches * 0.0254);
    // 512 bins x size, printed in whole metres.
    EXPECT_EQ(static_cast<std::uint32_t>(std::floor(bin_max_range_m(size))), row.max_range_m);
  }
  EXPECT_DOUBLE_EQ(bin_max_range_m(BinSize::inch_1), 13.0048);
  EXPECT_DOUBLE_EQ(bin_usable_range_m(BinSize::inches_256), 1664.0);  // reflective-sheet limit, §9
  EXPECT_DOUBLE_EQ(bin_usable_range_m(BinSize::inches_64), bin_max_range_m(BinSize::inches_64));
  EXPECT_FALSE(to_bin_size(9).has_value());
}

TEST(UlsConformance, U33_BinSizeLabelsOfTheInterfaceProgram) {  // §2 "Bin Size (Range) 2.5 (13) cm (M)"
  EXPECT_EQ(bin_size_info(BinSize::inch_1).interface_label, "2.5 (13)");
  EXPECT_EQ(bin_size_info(BinSize::inches_2).interface_label, "5.1 (26)");
  EXPECT_EQ(bin_size_info(BinSize::inches_128).interface_label, "326.4 (1664)");
  // U131: §2 Bin Size "the number in parenthesis is the maximum acquisition distance"; §9
  // "1664 m or 5459 ft (High-intensity Reflective Sheet)": 256-inch bins reach no further.
  EXPECT_EQ(bin_size_info(BinSize::inches_256).interface_label, "652.8 (1664)");
  EXPECT_DOUBLE_EQ(bin_size_m(BinSize::inch_1) * 100, 2.54);
}

TEST(UlsConformance, U23_FourToTwentyMilliamps) {      // §6 example: 0 m at 4 mA, 10 m at 20 mA
  EXPECT_DOUBLE_EQ(*loop_current_ma(5, 0, 10), 12.0);  // "5 x 1.6 mA = 8 mA + 4 mA ... = 12 mA"
  EXPECT_DOUBLE_EQ(*loop_current_ma(1, 0, 10) - *loop_current_ma(0, 0, 10), 1.6);  // 1.6 mA per metre
  EXPECT_DOUBLE_EQ(*loop_current_ma(0, 0, 10), 4.0);
  // §6 note: "9 volts ÷ 20 mA = a maximum sense resistor of 450 ohms".
  EXPECT_DOUBLE_EQ(max_sense_resistor_ohms(), 450.0);
  EXPECT_DOUBLE_EQ(*loop_current_ma(10, 0, 10), 20.0);
  EXPECT_DOUBLE_EQ(*loop_current_ma(-3, 0, 10), 4.0);   // clamped
  EXPECT_DOUBLE_EQ(*loop_current_ma(25, 0, 10), 20.0);  // clamped
  EXPECT_DOUBLE_EQ(*loop_current_ma(0, 10, 0), 20.0);   // inverted: AH < AL
  EXPECT_DOUBLE_EQ(*loop_current_ma(7.5, 10, 0), 8.0);
  EXPECT_FALSE(loop_current_ma(5, 5, 5).has_value());  // AL == AH, error 83
}

TEST(UlsTiming, TimeBetweenEventsSection3) {
  EXPECT_DOUBLE_EQ(pulses_to_seconds(0x0BB8, 3000), 1.0);  // "0BB8 hex (3000 decimal) ... 1 second"
  EXPECT_NEAR(tbe_max_seconds(3000), 22.0, 0.2);           // "approximately 22 seconds"
  EXPECT_EQ(max_tbe_pulses, 65535U);
  using Kind = TimeBetweenEvents::Kind;
  EXPECT_EQ(tbe_from_pulses(3000), (TimeBetweenEvents{Kind::pulses, 3000}));
  EXPECT_EQ(tbe_from_pulses(65535), (TimeBetweenEvents{Kind::pulses, 65535}));
  EXPECT_EQ(tbe_from_pulses(65536).kind, Kind::overflow);  // "will result in output of 0000"
  EXPECT_EQ(tbe_from_pulses(0).kind, Kind::overflow);
  EXPECT_EQ(std::string(encode_time_between_events(Address::none(), tbe_from_pulses(70'000))->wire()), "$0000\r");
  EXPECT_FALSE(tbe_seconds({Kind::overflow, 0}, 3000).has_value());
  EXPECT_FALSE(tbe_seconds({Kind::no_presence, 0}, 3000).has_value());
  EXPECT_DOUBLE_EQ(seconds_to_pulses(1.0, 3000), 3000.0);
}

TEST(UlsConformance, U34_LookDownResponse) {                 // §3 Look Down Mode
  EXPECT_DOUBLE_EQ(look_down_latency_s(3000), 0.010);        // "30 ... pulses ... 10 milliseconds"
  EXPECT_NEAR(look_down_uncertainty_s(3000), 330e-6, 5e-6);  // "± 330 µs"
  EXPECT_DOUBLE_EQ(look_down_uncertainty_s(3000), 1.0 / 3000);
  EXPECT_DOUBLE_EQ(pulses_to_seconds(rereference_pulses, 3000), 360.0);     // "1,080,000 ... approximately 6 minutes"
  EXPECT_NEAR(pulses_to_seconds(short_timeout_pulses, 3000), 2.67, 0.005);  // "8,000 ... approximately 3 seconds"
  EXPECT_DOUBLE_EQ(pulses_to_seconds(rereference_pulses, 1500), 720.0);     // inversely proportional to PRF (§2)
  EXPECT_EQ(trip_timeout_pulses(360), rereference_pulses);
  EXPECT_EQ(to_hex_text(short_timeout_pulses).view(), "1F40");
}

TEST(UlsTiming, DistancesInUserUnits) {  // §8 MU, §9 "1700 m or 5577 ft", "1664 m or 5459 ft"
  EXPECT_DOUBLE_EQ(to_metres(1.0, Units::feet), 0.3048);
  EXPECT_DOUBLE_EQ(to_metres(12.5, Units::metres), 12.5);
  EXPECT_EQ(std::floor(from_metres(1700, Units::feet)), 5577.0);
  EXPECT_EQ(std::floor(from_metres(1664, Units::feet)), 5459.0);
  EXPECT_DOUBLE_EQ(from_metres(0.3048, Units::feet), 1.0);
}

TEST(UlsTiming, HexTextOfPulseCounts) {
  EXPECT_EQ(to_hex_text(0).view(), "0");
  EXPECT_EQ(to_hex_text(0xFFFFFFFF).view(), "FFFFFFFF");
  EXPECT_FALSE(parse_trip_timeout("").has_value());
  EXPECT_FALSE(parse_trip_timeout("123456789").has_value());
  EXPECT_EQ(parse_trip_timeout("FFFFFFFF"), 0xFFFFFFFFU);
}

}  // namespace
}  // namespace rangekit::uls
