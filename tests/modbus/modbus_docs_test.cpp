// docs/modbus.md lists the register map and the command codes the face answers from: every
// row of the table is in the document as the table has it.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "build_paths.hpp"
#include "modbus/register_map.hpp"

namespace {

std::string document() {
  std::ifstream file(std::string(rangekit::test::source_dir()) + "/docs/modbus.md");
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

TEST(ModbusDocs, EveryInputRegisterBeforeTheTargetsIsListedAsTheTableHasIt) {
  const std::string doc = document();
  ASSERT_FALSE(doc.empty());
  for (const auto& row : rangekit::modbus::input_rows()) {
    if (row.address > rangekit::modbus::input::first_target_mm) break;  // the other targets share one line
    const std::string line = "| " + std::to_string(row.address) + " | " +
                             std::string(rangekit::modbus::register_type_name(row.type)) + " | " +
                             std::string(row.name) + " | " + std::string(row.unit) + (row.unit.empty() ? "| " : " | ") +
                             std::string(row.description) + " |";
    EXPECT_NE(doc.find(line), std::string::npos) << "docs/modbus.md lacks: " << line;
  }
}

TEST(ModbusDocs, EveryHoldingRegisterAndCommandCodeIsListed) {
  const std::string doc = document();
  for (const auto& row : rangekit::modbus::holding_rows()) {
    const std::string line = "| " + std::to_string(row.address) + " | " + std::string(row.name) + " | ";
    EXPECT_NE(doc.find(line), std::string::npos) << "docs/modbus.md lacks: " << line;
  }
  for (const auto& code : rangekit::modbus::command_codes()) {
    std::string action(code.action);
    if (!code.argument.empty()) action += " " + std::string(code.argument);
    const std::string line = "| " + std::to_string(code.code) + " | " + action + " | ";
    EXPECT_NE(doc.find(line), std::string::npos) << "docs/modbus.md lacks: " << line;
  }
}

}  // namespace
