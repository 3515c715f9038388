// LS5 §3, §5 and §7 worked examples (conformance L25).
#include <gtest/gtest.h>

#include "rangekit/ls5/model.hpp"

using namespace rangekit::ls5;

// §5: "LS5-100/200-485/E-I4-2-12-A": lower boundary 100 mm, range 200 mm, RS-485
// and Ethernet, 4-20 mA, 2 discrete outputs, 12 V, case 60x60x20 (A).
TEST(Ls5Model, OrderingCodeExampleOfSection5) {
  auto code = parse_ordering_code("LS5-100/200-485/E-I4-2-12-A");
  ASSERT_TRUE(code) << code.error().message;
  EXPECT_DOUBLE_EQ(code->lower_boundary_mm, 100.0);
  EXPECT_DOUBLE_EQ(code->range_mm, 200.0);
  EXPECT_EQ(code->interface, DigitalInterface::rs485_ethernet);
  EXPECT_TRUE(has_ethernet(*code));
  EXPECT_DOUBLE_EQ(code->analog.min, 4.0);
  EXPECT_DOUBLE_EQ(code->analog.max, 20.0);
  EXPECT_EQ(code->discrete_outputs, 2);
  EXPECT_EQ(code->supply_volts, 12);
  EXPECT_EQ(code->case_type, 'A');
}

TEST(Ls5Model, OrderingCodeFractionsAndOtherVariants) {
  // Table 5.1 model 0.5/5 has a fractional lower boundary ("0,5" in the table).
  auto code = parse_ordering_code("LS5-0.5/5-232-U10-0-24-B");
  ASSERT_TRUE(code) << code.error().message;
  EXPECT_DOUBLE_EQ(code->lower_boundary_mm, 0.5);
  EXPECT_EQ(code->interface, DigitalInterface::rs232);
  EXPECT_DOUBLE_EQ(code->analog.max, 10.0);
}

TEST(Ls5Model, BadOrderingCodesNameThePart) {
  auto missing = parse_ordering_code("LS5-100/200-485/E-I4-2-12");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("needs 7 parts"), std::string::npos);
  auto analog = parse_ordering_code("LS5-100/200-485-I7-2-12-A");
  ASSERT_FALSE(analog);
  EXPECT_NE(analog.error().message.find("analog output 'I7'"), std::string::npos);
  auto volts = parse_ordering_code("LS5-100/200-485-I4-2-48-A");
  ASSERT_FALSE(volts);
  EXPECT_NE(volts.error().message.find("supply '48'"), std::string::npos);
  EXPECT_FALSE(parse_ordering_code("LS5-100-485-I4-2-12-A"));
}

// §3 table 3.1 note 2: "for a sensor with a range of 5 mm, the digital interface
// error will be 5 mm · 0.0015 = 0.0075 mm"; analog ±0.25 %.
TEST(Ls5Model, ErrorLimitsOfTable31) {
  EXPECT_DOUBLE_EQ(digital_error_limit_mm(5.0), 0.0075);
  EXPECT_DOUBLE_EQ(analog_error_limit_mm(100.0), 0.25);
}

// §7: for the 0...20 mA interface the load must be more than 288 Ohm at 12 V,
// 438 at 15 V, 888 at 24 V, 1488 at 36 V ((0.02·U − 0.125) / 0.02², rounded up).
TEST(Ls5Model, MinimumLoadOfSection7) {
  EXPECT_DOUBLE_EQ(minimum_load_ohms(20, 12), 287.5);
  EXPECT_DOUBLE_EQ(minimum_load_ohms(20, 15), 437.5);
  EXPECT_DOUBLE_EQ(minimum_load_ohms(20, 24), 887.5);
  EXPECT_DOUBLE_EQ(minimum_load_ohms(20, 36), 1487.5);
}
