#include <gtest/gtest.h>

#include <array>

#include "rangekit/core/text.hpp"

namespace rangekit::text {
namespace {

TEST(Text, ParseUnsigned) {
  EXPECT_EQ(parse_unsigned("115200"), 115200U);
  EXPECT_EQ(parse_unsigned("0"), 0U);
  EXPECT_FALSE(parse_unsigned(""));
  EXPECT_FALSE(parse_unsigned("12a"));
  EXPECT_FALSE(parse_unsigned("-1"));
  EXPECT_FALSE(parse_unsigned(" 1"));
  EXPECT_FALSE(parse_unsigned("123456", 5));
  EXPECT_FALSE(parse_unsigned("65536", 5, 65535));
  EXPECT_FALSE(parse_unsigned("99999999999999999999"));
}

TEST(Text, ParseHex) {
  EXPECT_EQ(parse_hex("0BB8"), 3000U);
  EXPECT_EQ(parse_hex("107ac0"), 1080000U);
  EXPECT_FALSE(parse_hex("0BG8"));
  EXPECT_FALSE(parse_hex(""));
  EXPECT_FALSE(parse_hex("12345", 4));
}

TEST(Text, ParseDecimal) {
  EXPECT_DOUBLE_EQ(*parse_decimal("12.345"), 12.345);
  EXPECT_DOUBLE_EQ(*parse_decimal("-0.5"), -0.5);
  EXPECT_DOUBLE_EQ(*parse_decimal("7"), 7.0);
  EXPECT_DOUBLE_EQ(*parse_decimal("8,1234", ','), 8.1234);
  EXPECT_FALSE(parse_decimal("1.2.3"));
  EXPECT_FALSE(parse_decimal(".5"));
  EXPECT_FALSE(parse_decimal("5."));
  EXPECT_FALSE(parse_decimal("1e3"));
  EXPECT_FALSE(parse_decimal("-"));
  EXPECT_FALSE(parse_decimal("nan"));
  EXPECT_FALSE(parse_decimal("1234567890123456"));
}

TEST(Text, Split) {
  std::array<std::string_view, 4> fields{};
  EXPECT_EQ(split("BM,1,2,3", ',', fields), 4U);
  EXPECT_EQ(fields[3], "3");
  EXPECT_EQ(split("a,b,c,d,e", ',', fields), 5U);  // more than room: size + 1
  EXPECT_EQ(split("", ',', fields), 1U);
  EXPECT_EQ(split("a,", ',', fields), 2U);
  EXPECT_EQ(fields[1], "");
}

TEST(Text, WriteHex) {
  std::array<char, 6> out{};
  write_hex(0x107AC0, 6, out.data());
  EXPECT_EQ(std::string_view(out.data(), 6), "107AC0");
  write_hex(0xBB8, 4, out.data());
  EXPECT_EQ(std::string_view(out.data(), 4), "0BB8");
}

// LS5 table 9.1: "aa - parameter's address (HEX)", two digits in every frame; messages
// name addresses and bytes the same way.
TEST(Text, HexByte) {
  EXPECT_EQ(hex_byte(0x00), "00");
  EXPECT_EQ(hex_byte(0x0B), "0B");
  EXPECT_EQ(hex_byte(0x7F), "7F");
  EXPECT_EQ(hex_byte(0xFF), "FF");
}

}  // namespace
}  // namespace rangekit::text

TEST(Text, ClosestFindsTheNearMissAndNothingFar) {
  const std::vector<std::string> names{"mode", "median-points", "prf-hz", "port", "units"};
  EXPECT_EQ(rangekit::text::closest("moed", names), "mode");  // two neighbours swapped
  EXPECT_EQ(rangekit::text::closest("medain-points", names), "median-points");
  EXPECT_EQ(rangekit::text::closest("prot", names), "port");
  EXPECT_EQ(rangekit::text::closest("MODE", names), "mode");  // case is no typo
  EXPECT_EQ(rangekit::text::closest("frobnicate", names), std::nullopt);
  EXPECT_EQ(rangekit::text::closest("", names), std::nullopt);
  // As close to two: no guess.
  const std::vector<std::string> twins{"bat", "cat"};
  EXPECT_EQ(rangekit::text::closest("hat", twins), std::nullopt);
}
