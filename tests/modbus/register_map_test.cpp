// The register map's table and the word orders, against values worked by hand.
#include <gtest/gtest.h>

#include <bit>
#include <sstream>

#include "modbus/register_map.hpp"

namespace {

using rangekit::modbus::WordOrder;

// 1.0f is 0x3F800000: A=3F B=80 C=00 D=00.
TEST(ModbusWordOrder, EachOrderLaysOutTheBytesItNames) {
  const auto one = std::bit_cast<std::uint32_t>(1.0F);
  ASSERT_EQ(one, 0x3F800000U);
  EXPECT_EQ(rangekit::modbus::words_of_u32(one, WordOrder::abcd), (std::array<std::uint16_t, 2>{0x3F80, 0x0000}));
  EXPECT_EQ(rangekit::modbus::words_of_u32(one, WordOrder::cdab), (std::array<std::uint16_t, 2>{0x0000, 0x3F80}));
  EXPECT_EQ(rangekit::modbus::words_of_u32(one, WordOrder::badc), (std::array<std::uint16_t, 2>{0x803F, 0x0000}));
  EXPECT_EQ(rangekit::modbus::words_of_u32(one, WordOrder::dcba), (std::array<std::uint16_t, 2>{0x0000, 0x803F}));
  // 0x11223344: A=11 B=22 C=33 D=44.
  EXPECT_EQ(rangekit::modbus::words_of_u32(0x11223344U, WordOrder::dcba),
            (std::array<std::uint16_t, 2>{0x4433, 0x2211}));
  for (const WordOrder order : {WordOrder::abcd, WordOrder::cdab, WordOrder::badc, WordOrder::dcba}) {
    const auto words = rangekit::modbus::words_of_u32(0x11223344U, order);
    EXPECT_EQ(rangekit::modbus::u32_of_words(words[0], words[1], order), 0x11223344U)
        << rangekit::modbus::word_order_name(order);
  }
}

TEST(ModbusWordOrder, NamesReadInAnyCaseAndOthersAreRefused) {
  EXPECT_EQ(rangekit::modbus::parse_word_order("cdab"), WordOrder::cdab);
  EXPECT_EQ(rangekit::modbus::parse_word_order("DCBA"), WordOrder::dcba);
  EXPECT_FALSE(rangekit::modbus::parse_word_order("ABDC"));
  EXPECT_FALSE(rangekit::modbus::parse_word_order(""));
}

// Rows in address order, none overlapping another, the last one ending the map.
TEST(ModbusRegisterMap, RowsFollowEachOtherWithoutOverlap) {
  std::size_t next = 0;
  for (const auto& row : rangekit::modbus::input_rows()) {
    EXPECT_GE(row.address, next) << row.name;
    next = row.address + rangekit::modbus::words_of(row.type);
  }
  EXPECT_EQ(next, rangekit::modbus::input::count);
  EXPECT_EQ(rangekit::modbus::input_rows().back().name, "target_15_mm");
}

TEST(ModbusRegisterMap, CsvHasARowPerRegisterOfEveryUnit) {
  const std::vector<std::pair<std::uint8_t, std::string>> units{{1, "belt"}, {9, "bay, north"}};
  const std::string read_only = rangekit::modbus::write_register_map(units, WordOrder::cdab, false);
  std::istringstream lines(read_only);
  std::string header;
  std::getline(lines, header);
  EXPECT_EQ(header, "unit,sensor,table,register,type,name,unit_of_measure,word_order,description");
  std::size_t rows = 0;
  for (std::string line; std::getline(lines, line);) ++rows;
  EXPECT_EQ(rows, 2 * rangekit::modbus::input_rows().size());
  EXPECT_NE(read_only.find("1,belt,input,0,float32,reading_mm,mm,CDAB,"), std::string::npos) << read_only;
  EXPECT_NE(read_only.find("9,\"bay, north\",input,4,bits16,status,,,"), std::string::npos);
  EXPECT_EQ(read_only.find(",holding,"), std::string::npos);
  const std::string writable = rangekit::modbus::write_register_map(units, WordOrder::abcd, true);
  EXPECT_NE(writable.find("1,belt,holding,0,uint16,command,,,"), std::string::npos);
}

}  // namespace
