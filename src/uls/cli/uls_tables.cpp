// The ULS's registries for `rangekit tables`: its commands (§8) and error numbers (§10).
#include <fmt/core.h>

#include <array>
#include <string>

#include "cli/text_table.hpp"
#include "rangekit/uls/commands.hpp"
#include "rangekit/uls/errors.hpp"
#include "uls/cli/uls_cli.hpp"

namespace rangekit::cli {
namespace {

std::string range_text(const uls::CommandInfo& command) {
  if (!command.value_names.empty()) {
    std::string text;
    for (const auto& value : command.value_names) {
      if (!text.empty()) text += ", ";
      text += fmt::format("{} {}", value.value, value.name);
    }
    return text;
  }
  if (command.kind == uls::ValueKind::none || command.kind == uls::ValueKind::measurement ||
      command.kind == uls::ValueKind::text || command.kind == uls::ValueKind::status) {
    return "-";
  }
  return fmt::format("{:g}..{:g} {}", command.min, command.max, command.unit);
}

void print_commands(bool markdown) {
  TextTable table({"mnemonic", "name", "cli name", "access", "values", "error", "while measuring", "section"});
  for (const auto& command : uls::command_table()) {
    table.add({std::string(command.mnemonic), std::string(command.title), std::string(command.cli_name),
               std::string(uls::access_name(command.access)), range_text(command),
               command.value_error == 0 ? "-" : std::to_string(command.value_error),
               command.rejected_while_measuring ? "error 31" : "accepted", std::string(command.reference)});
  }
  table.print(markdown);
}

void print_errors(bool markdown) {
  TextTable table({"number", "explanation", "display", "group", "service"});
  for (const auto& error : uls::error_table()) {
    table.add({std::to_string(error.number), std::string(error.explanation), std::string(error.display),
               std::string(uls::error_group_name(error.group)), error.service_required ? "LTI" : "-"});
  }
  table.print(markdown);
}

constexpr std::array tables{CliTable{"commands", print_commands}, CliTable{"errors", print_errors}};

}  // namespace

const std::span<const CliTable> uls_tables{tables};

}  // namespace rangekit::cli
