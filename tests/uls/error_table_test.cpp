// §10 Error Numbers, typed from the document (U22).
#include <gtest/gtest.h>

#include <string>

#include "rangekit/uls/errors.hpp"

namespace rangekit::uls {
namespace {

TEST(UlsErrorTable, HoldsOneAndFourToEightySeven) {
  const auto table = error_table();
  ASSERT_EQ(table.size(), 85U);
  EXPECT_EQ(table.front().number, 1);
  int expected = 4;
  for (std::size_t i = 1; i < table.size(); ++i) EXPECT_EQ(table[i].number, expected++);
  EXPECT_EQ(table.back().number, 87);
  EXPECT_EQ(find_error(0), nullptr);
  EXPECT_EQ(find_error(2), nullptr);
  EXPECT_EQ(find_error(3), nullptr);
  EXPECT_EQ(find_error(88), nullptr);
  EXPECT_EQ(find_error(-1), nullptr);
  for (const ErrorInfo& row : table) {
    EXPECT_FALSE(row.explanation.empty()) << row.number;
    EXPECT_FALSE(row.display.empty()) << row.number;
  }
}

struct Printed {
  int number;
  std::string_view explanation;
  std::string_view display;
};

TEST(UlsErrorTable, SpotChecksAsPrinted) {
  const Printed rows[] = {
      {1, "General Command Interface Error", "Invalid Command"},
      {4, "Lock Not Found", "Target Not Found"},
      {5, "Average Weight Not Filled", "Average Not Filled"},
      {9, "PTFCAL Bad Status Error", "ER 009"},
      {31, "No Serial While Measuring Error", "Instrument Is Already Measuring"},
      {32, "Invalid Rep Rate", "Invalid PRF"},
      {33, "Invalid Input Base", "ER 033"},
      {34, "Invalid Baud Rate", "Invalid Baud Rate"},
      {35, "Invalid Average Weight", "Invalid Average Weight"},
      {49, "Pulse Per Output Must Be Greater Than Average Weight", "PPO Must Be Greater Than Average Weight"},
      {50, "Dropped Pulse", "ER 050"},
      {59, "BAD PTF Table Checksum", "BAD PTF Table Checksum"},
      {78, "Invalid Command for Measurement Mode", "ER 078"},
      {82, "Unit Address Not Assigned", "Unit Address Not Assigned"},
      {83, "Invalid MA420 Range", "Invalid Current Loop Range"},
      {84, "Invalid Port", "Invalid Port"},
      {85, "Invalid Measurement Mode", "Invalid Measurement Mode"},
      {86, "Instrument Not Measuring", "Instrument Not Measuring"},
      {87, "Invalid Minimum Pulse Width", "Invalid Minimum Pulse Width"},
  };
  for (const Printed& row : rows) {
    SCOPED_TRACE(row.number);
    const ErrorInfo* info = find_error(row.number);
    ASSERT_NE(info, nullptr);
    EXPECT_EQ(info->explanation, row.explanation);
    EXPECT_EQ(info->display, row.display);
  }
}

TEST(UlsErrorTable, GroupsFollowTheSubheadings) {  // §10 "Interrupt Error Codes", "Table Checksums", ...
  EXPECT_EQ(find_error(49)->group, ErrorGroup::general);
  EXPECT_EQ(find_error(50)->group, ErrorGroup::interrupt);
  EXPECT_EQ(find_error(58)->group, ErrorGroup::interrupt);
  EXPECT_EQ(find_error(59)->group, ErrorGroup::table_checksum);
  EXPECT_EQ(find_error(81)->group, ErrorGroup::table_checksum);
  EXPECT_EQ(find_error(82)->group, ErrorGroup::rs485);
  EXPECT_EQ(find_error(83)->group, ErrorGroup::current_loop);
  EXPECT_EQ(find_error(87)->group, ErrorGroup::current_loop);
  EXPECT_EQ(error_group_name(ErrorGroup::rs485), "RS485");
}

TEST(UlsConformance, U22_ServiceRequiredMarks) {
  for (const ErrorInfo& row : error_table()) {
    const bool marked = row.number == 10 || row.number == 23 || row.number == 28 || row.number == 47;
    EXPECT_EQ(row.service_required, marked) << row.number;
  }
  EXPECT_EQ(find_error(10)->explanation, "ADC Error");
  EXPECT_EQ(find_error(23)->explanation, "Laser CPU Failed RAM Test");
  EXPECT_EQ(find_error(28)->explanation, "HV CLK Frequency Too High Error");
  EXPECT_EQ(find_error(47)->explanation, "SPI Busy");
}

TEST(UlsErrorTable, NamedNumbersMatchTheTable) {
  EXPECT_EQ(find_error(error_number::already_measuring)->display, "Instrument Is Already Measuring");
  EXPECT_EQ(find_error(error_number::ppo_not_greater_than_weight)->number, 49);
  EXPECT_EQ(find_error(error_number::invalid_port)->display, "Invalid Port");
  EXPECT_EQ(find_error(error_number::target_not_found)->display, "Target Not Found");
  EXPECT_EQ(find_error(error_number::average_not_filled)->display, "Average Not Filled");
}

}  // namespace
}  // namespace rangekit::uls
