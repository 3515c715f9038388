// Table 9.1 as data: one row per command, checked against the table as printed.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "rangekit/ls5/commands.hpp"

using namespace rangekit::ls5;

TEST(Ls5CommandTable, TwelveCommandsOfTable91) {
  const auto table = command_table();
  ASSERT_EQ(table.size(), 12U);
  const char* codes[] = {"ID", "R", "W", "FL", "ON", "OF", "FX", "ST", "SB", "FR", "LR", "DF"};
  for (std::size_t i = 0; i < table.size(); ++i) {
    EXPECT_EQ(table[i].code, codes[i]);
    EXPECT_EQ(&command_info(table[i].id), &table[i]);
    EXPECT_EQ(find_command_by_code(codes[i]), &table[i]);
    EXPECT_EQ(find_command_by_cli_name(table[i].cli_name), &table[i]);
  }
  EXPECT_EQ(find_command_by_code("on"), nullptr);  // L16
  EXPECT_EQ(find_command_by_code("XX"), nullptr);
}

TEST(Ls5CommandTable, NamesAsPrinted) {
  EXPECT_EQ(command_info(CommandId::identification).name, "Identification");
  EXPECT_EQ(command_info(CommandId::read_parameter).name, "Read the parameter");
  EXPECT_EQ(command_info(CommandId::write_parameter).name, "Write the parameter");
  EXPECT_EQ(command_info(CommandId::store_to_flash).name,
            "Save parameters to non-volatile memory (Store current parameters to FLASH)");
  EXPECT_EQ(command_info(CommandId::turn_on).name, "Turn on the sensor");
  EXPECT_EQ(command_info(CommandId::turn_off).name, "Turn off the sensor");
  EXPECT_EQ(command_info(CommandId::latch_result).name, "Latch the result");
  EXPECT_EQ(command_info(CommandId::start_stream).name, "Start the result stream");
  EXPECT_EQ(command_info(CommandId::stop_stream).name, "Stop the stream");
  EXPECT_EQ(command_info(CommandId::read_latched).name, "Read the latched result");
  EXPECT_EQ(command_info(CommandId::read_last).name, "Read the last result");
  EXPECT_EQ(command_info(CommandId::restore_defaults).name, "Restoring default parameters");
}

TEST(Ls5CommandTable, RequestAndResponseForms) {
  EXPECT_EQ(command_info(CommandId::read_parameter).request, RequestForm::parameter_address);
  EXPECT_EQ(command_info(CommandId::read_parameter).response, ResponseForm::parameter_value);
  EXPECT_EQ(command_info(CommandId::write_parameter).request, RequestForm::address_and_value);
  EXPECT_EQ(command_info(CommandId::write_parameter).response, ResponseForm::echo);
  EXPECT_EQ(command_info(CommandId::identification).response, ResponseForm::identification);
  EXPECT_EQ(command_info(CommandId::start_stream).response, ResponseForm::stream);
  EXPECT_EQ(command_info(CommandId::read_latched).response, ResponseForm::result);
  EXPECT_EQ(command_info(CommandId::read_last).response, ResponseForm::result);
  for (const CommandId id : {CommandId::store_to_flash, CommandId::turn_on, CommandId::turn_off,
                             CommandId::latch_result, CommandId::stop_stream, CommandId::restore_defaults}) {
    EXPECT_EQ(command_info(id).request, RequestForm::no_argument);
    EXPECT_EQ(command_info(id).response, ResponseForm::echo);
  }
  EXPECT_EQ(reply_argument_length(command_info(CommandId::write_parameter)), 4U);
  EXPECT_EQ(reply_argument_length(command_info(CommandId::read_parameter)), 4U);
  EXPECT_EQ(reply_argument_length(command_info(CommandId::read_last)), 5U);
  EXPECT_EQ(reply_argument_length(command_info(CommandId::turn_on)), 0U);
}

TEST(Ls5CommandTable, BroadcastNotes) {
  // Notes 1 and 2 of table 9.1 mark W, FL, ON, OF, FX, SB and DF.
  const std::set<std::string> marked = {"W", "FL", "ON", "OF", "FX", "SB", "DF"};
  for (const CommandInfo& command : command_table()) {
    const bool in_notes = marked.count(std::string(command.code)) == 1;
    EXPECT_EQ(command.broadcast_allowed, in_notes) << command.code;
    EXPECT_EQ(command.silent_on_broadcast, in_notes) << command.code;
  }
}

TEST(Ls5CommandTable, CliNamesAreUniqueAndLowerCase) {
  std::set<std::string_view> names;
  for (const CommandInfo& command : command_table()) {
    EXPECT_TRUE(names.insert(command.cli_name).second) << command.cli_name;
    for (const char c : command.cli_name) EXPECT_TRUE((c >= 'a' && c <= 'z') || c == '-') << command.cli_name;
  }
}
