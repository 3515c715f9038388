// §8 formulas: result codes (8.1, 8.2, 8.5), analog output (8.3), discrete outputs
// (8.4), latching recalculation (8.6, 8.7), derivative, serial timing (§8.4).
// Expected values are worked out by hand in the comments.
#include <gtest/gtest.h>

#include "rangekit/ls5/formulas.hpp"
#include "rangekit/ls5/result_code.hpp"
#include "test_helpers.hpp"

using namespace rangekit;
using namespace rangekit::ls5;
using ls5_test::U8s;

namespace {
const AnalogLimits full_scale{0, 50000};
ResultCode code(std::uint16_t value) { return classify_result_code(value); }
}  // namespace

// ---- §8.9, formulas 8.1 and 8.2, conformance L7 ----

TEST(Ls5Formulas, DistanceFormula81) {
  // 40 mm × 25000 / 50000 = 20 mm; 40 × 0 / 50000 = 0; 40 × 50000 / 50000 = 40.
  EXPECT_DOUBLE_EQ(distance_mm(25000, 40.0), 20.0);
  EXPECT_DOUBLE_EQ(distance_mm(0, 40.0), 0.0);
  EXPECT_DOUBLE_EQ(distance_mm(50000, 40.0), 40.0);
  // §9.2 sensor, range 40,001 mm: 40.001 × 10000 / 50000 = 8.0002 mm.
  EXPECT_DOUBLE_EQ(distance_mm(10000, 40.001), 8.0002);
  EXPECT_DOUBLE_EQ(distance_from_code(code(12500), 100.0).value_or(-1), 25.0);
}

TEST(Ls5Formulas, DerivativeFormula82) {
  // 40 × (25000 − 25000) / 50000 = 0; 40 × (50000 − 25000) / 50000 = 20; 40 × (0 − 25000) / 50000 = −20.
  EXPECT_DOUBLE_EQ(derivative_mm(25000, 40.0), 0.0);
  EXPECT_DOUBLE_EQ(derivative_mm(50000, 40.0), 20.0);
  EXPECT_DOUBLE_EQ(derivative_mm(0, 40.0), -20.0);
  EXPECT_DOUBLE_EQ(derivative_mm(26000, 100.0), 2.0);  // 100 × 1000 / 50000
}

TEST(Ls5Formulas, SpecialCodesL7) {
  const auto none_yet = make_result_code(65534);
  ASSERT_TRUE(none_yet.ok());
  EXPECT_EQ(none_yet->kind, CodeKind::no_measurement_yet);
  const auto no_signal = make_result_code(65535);
  ASSERT_TRUE(no_signal.ok());
  EXPECT_EQ(no_signal->kind, CodeKind::no_signal);
  EXPECT_FALSE(distance_from_code(*none_yet, 40.0).ok());
  EXPECT_FALSE(distance_from_code(*no_signal, 40.0).ok());
  EXPECT_NE(distance_from_code(*no_signal, 40.0).error().message.find("no signal"), std::string::npos);
  for (const std::uint32_t invalid : {50001U, 60000U, 65533U, 65536U, 99999U}) {
    const auto result = make_result_code(invalid);
    ASSERT_FALSE(result.ok()) << invalid;
    EXPECT_EQ(result.error().code, Errc::out_of_range);
  }
  EXPECT_TRUE(make_result_code(0).ok());
  EXPECT_TRUE(make_result_code(50000).ok());
}

TEST(Ls5Formulas, CodeFromDistanceFormula85L23) {
  // §8.14: 20 mm / 100 mm × 50000 = 10000.
  EXPECT_EQ(code_from_distance(20.0, 100.0).value_or(0), 10000);
  EXPECT_EQ(code_from_distance(100.0, 100.0).value_or(0), 50000);
  EXPECT_EQ(code_from_distance(0.0, 100.0).value_or(1), 0);
  // 1 / 3 × 50000 = 16666.67 → 16667.
  EXPECT_EQ(code_from_distance(1.0, 3.0).value_or(0), 16667);
  // 2.5 / 50000 × 50000 = 2.5 → 3 (halves away from zero).
  EXPECT_EQ(code_from_distance(2.5, 50000.0).value_or(0), 3);
  EXPECT_FALSE(code_from_distance(100.1, 100.0).ok());
  EXPECT_FALSE(code_from_distance(-1.0, 100.0).ok());
  EXPECT_FALSE(code_from_distance(10.0, 0.0).ok());
}

// ---- §8.10, formula 8.3, conformance L8 ----

TEST(Ls5Formulas, AnalogOutputLinearL8) {
  // 4 + 16 × 25000 / 50000 = 12 mA.
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, full_scale, 25000), 12.0);
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, full_scale, 0), 4.0);
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, full_scale, 50000), 20.0);
  EXPECT_DOUBLE_EQ(analog_output(current_0_20_mA, full_scale, 12500), 5.0);  // 20 × 1/4
  EXPECT_DOUBLE_EQ(analog_output(voltage_0_10_V, full_scale, 25000), 5.0);

  // K_n = 10000, K_v = 30000: held below K_n and above K_v; 20000 is half way: 12 mA.
  const AnalogLimits window{10000, 30000};
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, window, 5000), 4.0);
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, window, 10000), 4.0);
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, window, 15000), 8.0);  // 4 + 16 × 5000/20000
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, window, 20000), 12.0);
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, window, 30000), 20.0);
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, window, 40000), 20.0);
}

TEST(Ls5Formulas, AnalogOutputInvertedL8) {
  // K_v = 10000 < K_n = 30000: A_max at and below K_v, A_min at and above K_n.
  const AnalogLimits inverted{30000, 10000};
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, inverted, 5000), 20.0);
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, inverted, 10000), 20.0);
  // 4 + 16 × (25000 − 30000) / (10000 − 30000) = 4 + 16 × 0.25 = 8 mA.
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, inverted, 25000), 8.0);
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, inverted, 20000), 12.0);
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, inverted, 30000), 4.0);
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, inverted, 45000), 4.0);
  // K_v = K_n: A_min, formula 8.3's "A = A_min, if ... K_v = K_n" (L90).
  const AnalogLimits flat{20000, 20000};
  for (const std::uint16_t k : {std::uint16_t{0}, std::uint16_t{20000}, std::uint16_t{50000}}) {
    EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, flat, k), 4.0);
  }
}

TEST(Ls5Formulas, AnalogOutputWithoutSignalL8) {
  const ResultCode no_signal = code(code_no_signal);
  const ResultCode none_yet = code(code_no_measurement_yet);
  // Last output 18 mA (code 43750 → 4 + 16 × 0.875): above mid-scale 12 mA → 20 mA.
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, full_scale, no_signal, std::uint16_t{43750}), 20.0);
  // Last output 5.6 mA (code 5000): below mid-scale → 4 mA.
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, full_scale, no_signal, std::uint16_t{5000}), 4.0);
  // Exactly mid-scale counts as the upper half.
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, full_scale, no_signal, std::uint16_t{25000}), 20.0);
  // Inverted: last code 5000 gave 20 mA, so no signal gives 20 mA: the extreme "depending on the
  // last measured value", kept in the direction the output had (L91).
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, AnalogLimits{30000, 10000}, no_signal, std::uint16_t{5000}), 20.0);
  // No measurement yet, or no signal before any result: A_min (§8.2).
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, full_scale, none_yet, std::uint16_t{40000}), 4.0);
  EXPECT_DOUBLE_EQ(analog_output(current_4_20_mA, full_scale, no_signal, std::nullopt), 4.0);
  EXPECT_DOUBLE_EQ(analog_output(voltage_0_10_V, full_scale, code(25000), std::nullopt), 5.0);
}

// ---- §8.11, formula 8.4, figure 8.6, conformance L9 ----

TEST(Ls5Formulas, DiscreteOutputFigure86L9) {
  // Figure 8.6: first swing 20000, second 40000.
  const Swings swings{20000, 40000};
  const DiscreteOutputSetting initial_zero{true, false};
  const DiscreteOutputSetting initial_one{true, true};
  struct Case {
    std::uint16_t k;
    bool between;
  };
  const Case cases[] = {{0, false},     {19999, false},          {20000, true},
                        {30000, true},  {40000, true},           {40001, false},
                        {50000, false}, {code_no_signal, false}, {code_no_measurement_yet, false}};
  for (const Case& c : cases) {
    EXPECT_EQ(discrete_output_state(initial_zero, swings, c.k), c.between) << c.k;
    EXPECT_EQ(discrete_output_state(initial_one, swings, c.k), !c.between) << c.k;
    EXPECT_FALSE(discrete_output_state(DiscreteOutputSetting{false, true}, swings, c.k)) << c.k;
  }
}

TEST(Ls5Formulas, DiscreteOutputsSettingParameter15L9) {
  // Table 9.2 example "12": output 1 enabled with initial 0, output 2 enabled with initial 1.
  const auto setting = decode_discrete_outputs(0x12);
  ASSERT_TRUE(setting.ok());
  EXPECT_EQ(setting->output1, (DiscreteOutputSetting{true, false}));
  EXPECT_EQ(setting->output2, (DiscreteOutputSetting{true, true}));
  const auto off = decode_discrete_outputs(0x00);
  ASSERT_TRUE(off.ok());
  EXPECT_FALSE(off->output1.enabled);
  EXPECT_FALSE(off->output2.enabled);
  for (const std::uint8_t valid : U8s{0x00, 0x01, 0x02, 0x10, 0x11, 0x12, 0x20, 0x21, 0x22}) {
    const auto decoded = decode_discrete_outputs(valid);
    ASSERT_TRUE(decoded.ok()) << int{valid};
    EXPECT_EQ(encode_discrete_outputs(*decoded), valid);
  }
  for (const std::uint8_t invalid : U8s{0x03, 0x30, 0x13, 0xFF}) EXPECT_FALSE(decode_discrete_outputs(invalid).ok());
}

// ---- §8.14, formulas 8.5-8.7, conformance L10 ----

TEST(Ls5Formulas, WeldingExampleSection814L10) {
  // 100 mm sensor, ±10 mm = 20 mm span: D = 20 / 100 × 50000 = 10000 (formula 8.5).
  const auto span = code_from_distance(20.0, 100.0);
  ASSERT_TRUE(span.ok());
  EXPECT_EQ(*span, 10000);
  // Latched K = 25000: G_min = 25000 − 5000 = 20000 = 0x4E20, G_max = 30000 = 0x7530.
  EXPECT_EQ(latch_lower_limit(25000, *span), 0x4E20);
  EXPECT_EQ(latch_upper_limit(25000, *span), 0x7530);

  // Latching 09: lower limit of output 1 (16/17), upper limit of output 2 (1C/1D), to ROM.
  const auto outcome = recalculate_on_latch(0x09, code(25000), 10000, *span);
  ASSERT_TRUE(outcome.ok()) << outcome.error().describe();
  EXPECT_TRUE(outcome->recalculated);
  EXPECT_TRUE(outcome->to_rom);
  EXPECT_EQ(outcome->lower, 20000);
  EXPECT_EQ(outcome->upper, 30000);
  ASSERT_EQ(outcome->writes.count, 4U);
  EXPECT_EQ(outcome->writes.items[0], (ParameterWrite{0x16, 0x20}));
  EXPECT_EQ(outcome->writes.items[1], (ParameterWrite{0x17, 0x4E}));
  EXPECT_EQ(outcome->writes.items[2], (ParameterWrite{0x1C, 0x30}));
  EXPECT_EQ(outcome->writes.items[3], (ParameterWrite{0x1D, 0x75}));
}

TEST(Ls5Formulas, LatchLimitsClampAndRoundL10) {
  // 2000 − 5000 = −3000 → 0; 2000 + 5000 = 7000.
  EXPECT_EQ(latch_lower_limit(2000, 10000), 0);
  EXPECT_EQ(latch_upper_limit(2000, 10000), 7000);
  // 48000 + 5000 = 53000 → 50000.
  EXPECT_EQ(latch_upper_limit(48000, 10000), 50000);
  EXPECT_EQ(latch_lower_limit(48000, 10000), 43000);
  // D = 0xFFFF: 25000 ∓ 32767.5 → 0 and 50000.
  EXPECT_EQ(latch_lower_limit(25000, 0xFFFF), 0);
  EXPECT_EQ(latch_upper_limit(25000, 0xFFFF), 50000);
  // D odd: 25000 − 5000.5 = 19999.5 → 20000; 25000 + 5000.5 = 30000.5 → 30001 (halves away from zero).
  EXPECT_EQ(latch_lower_limit(25000, 10001), 20000);
  EXPECT_EQ(latch_upper_limit(25000, 10001), 30001);
  // D = 1 at K = 0: −0.5 → −1 → 0; +0.5 → 1.
  EXPECT_EQ(latch_lower_limit(0, 1), 0);
  EXPECT_EQ(latch_upper_limit(0, 1), 1);
  // D = 1 at K = 50000: 49999.5 → 50000; 50000.5 → 50001 → 50000.
  EXPECT_EQ(latch_lower_limit(50000, 1), 50000);
  EXPECT_EQ(latch_upper_limit(50000, 1), 50000);
}

TEST(Ls5Formulas, LatchingModesL10) {
  const std::uint16_t analog_span = 2000;    // G = 25000 ∓ 1000
  const std::uint16_t discrete_span = 4000;  // G = 25000 ∓ 2000
  const ResultCode k = code(25000);
  struct Case {
    std::uint8_t mode;
    bool to_rom;
    std::array<std::uint8_t, 4> addresses;
    std::uint16_t lower;
    std::uint16_t upper;
  };
  const Case cases[] = {
      {0x02, false, {0x11, 0x12, 0x13, 0x14}, 24000, 26000}, {0x03, true, {0x11, 0x12, 0x13, 0x14}, 24000, 26000},
      {0x04, false, {0x16, 0x17, 0x18, 0x19}, 23000, 27000}, {0x05, true, {0x16, 0x17, 0x18, 0x19}, 23000, 27000},
      {0x06, false, {0x1A, 0x1B, 0x1C, 0x1D}, 23000, 27000}, {0x07, true, {0x1A, 0x1B, 0x1C, 0x1D}, 23000, 27000},
      {0x08, false, {0x16, 0x17, 0x1C, 0x1D}, 23000, 27000}, {0x09, true, {0x16, 0x17, 0x1C, 0x1D}, 23000, 27000},
  };
  for (const Case& c : cases) {
    const auto outcome = recalculate_on_latch(c.mode, k, analog_span, discrete_span);
    ASSERT_TRUE(outcome.ok()) << int{c.mode};
    EXPECT_TRUE(outcome->recalculated);
    EXPECT_EQ(outcome->to_rom, c.to_rom) << int{c.mode};
    ASSERT_EQ(outcome->writes.count, 4U);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(outcome->writes.items[i].address, c.addresses[i]) << int{c.mode};
    // Low byte then high byte of G_min, then of G_max.
    EXPECT_EQ(outcome->writes.items[0].value, c.lower & 0xFF);
    EXPECT_EQ(outcome->writes.items[1].value, c.lower >> 8);
    EXPECT_EQ(outcome->writes.items[2].value, c.upper & 0xFF);
    EXPECT_EQ(outcome->writes.items[3].value, c.upper >> 8);
  }
  // 00 and 01: latch only, nothing recalculated.
  for (const std::uint8_t mode : U8s{0x00, 0x01}) {
    const auto outcome = recalculate_on_latch(mode, k, analog_span, discrete_span);
    ASSERT_TRUE(outcome.ok());
    EXPECT_FALSE(outcome->recalculated);
    EXPECT_EQ(outcome->writes.count, 0U);
  }
  // A latched special code changes nothing.
  const auto no_signal = recalculate_on_latch(0x09, code(code_no_signal), analog_span, discrete_span);
  ASSERT_TRUE(no_signal.ok());
  EXPECT_FALSE(no_signal->recalculated);
  EXPECT_EQ(no_signal->writes.count, 0U);
  const auto bad = recalculate_on_latch(0x0A, k, analog_span, discrete_span);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code, Errc::out_of_range);
}

// ---- §8.8, conformance L11 ----

TEST(Ls5Formulas, DerivativeCodeL11) {
  EXPECT_EQ(derivative_code(100, 100), 25000);
  EXPECT_EQ(derivative_code(30000, 25000), 30000);                              // 25000 + 5000
  EXPECT_EQ(derivative_code(20000, 25000), 20000);                              // 25000 − 5000
  EXPECT_EQ(derivative_code(0, 50000), 0);                                      // 25000 − 50000 → 0
  EXPECT_EQ(derivative_code(50000, 0), 50000);                                  // 25000 + 50000 → 50000
  EXPECT_DOUBLE_EQ(derivative_mm(derivative_code(30000, 25000), 100.0), 10.0);  // 100 × 5000 / 50000
}

// ---- §8.4, conformance L13 ----

TEST(Ls5Formulas, SerialTimingSection84L13) {
  const ByteFormat n81 = *byte_format_from_code(0x00);
  EXPECT_EQ(bits_per_byte(n81), 10U);  // start + 8 data + stop
  EXPECT_EQ(bits_per_byte(*byte_format_from_code(0x01)), 11U);
  EXPECT_EQ(bits_per_byte(*byte_format_from_code(0x03)), 11U);
  EXPECT_EQ(bits_per_byte(*byte_format_from_code(0x05)), 12U);

  // "7·10·1/115200 = 0.61 ms"; "7·10·1/57600 = 1.2 ms".
  EXPECT_NEAR(stream_record_time_ms(115200, n81), 0.61, 0.005);
  EXPECT_NEAR(stream_record_time_ms(57600, n81), 1.2, 0.05);
  EXPECT_DOUBLE_EQ(stream_record_time_ms(57600, n81), 70.0 * 1000.0 / 57600.0);

  // "only possible to get a 1 kHz speed ... 8-bit data without parity if the baud rate is 115200 or higher".
  EXPECT_GE(max_stream_rate_hz(115200, n81), 1000.0);
  EXPECT_LT(max_stream_rate_hz(57600, n81), 1000.0);
  const auto slowest = slowest_baud_for_stream_rate(1000.0, n81, firmware_6_0);
  ASSERT_TRUE(slowest.has_value());
  EXPECT_EQ(slowest->baud, 115200U);
  EXPECT_EQ(slowest->code, 0x05);
  // 2 kHz needs 140000 baud: 230400, which needs LS5.6.0.
  EXPECT_EQ(slowest_baud_for_stream_rate(2000.0, n81, firmware_6_0)->baud, 230400U);
  EXPECT_FALSE(slowest_baud_for_stream_rate(2000.0, n81, FirmwareVersion{5, 0}).has_value());
}

TEST(Ls5Formulas, OutputPeriodSection84) {
  // Figure 8.1: T = n × t, n = 2; t = 1 ms (000A).
  EXPECT_DOUBLE_EQ(output_period_ms(0x000A, 2), 2.0);
  // Table 9.2 note 1: n = 01 gives T = t; n = FF gives 255 · t.
  EXPECT_DOUBLE_EQ(output_period_ms(0x0064, 1), 10.0);
  EXPECT_DOUBLE_EQ(output_period_ms(0x0064, 0xFF), 2550.0);
}
