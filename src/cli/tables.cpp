// `rangekit tables`: the command, error and parameter registries as text or
// Markdown, straight from the tables the codecs use (so help and docs cannot
// drift from the code).
#include <fmt/core.h>

#include <algorithm>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "rangekit/ls5/commands.hpp"
#include "rangekit/ls5/parameters.hpp"
#include "rangekit/uls/commands.hpp"
#include "rangekit/uls/errors.hpp"

namespace rangekit::cli {
namespace {

struct TableOptions {
  std::string which;
  bool markdown = false;
};

// Rows are collected first so plain columns can be aligned.
class Table {
 public:
  explicit Table(std::vector<std::string> header) : rows_{std::move(header)} {}
  void add(std::vector<std::string> cells) { rows_.push_back(std::move(cells)); }

  void print(bool markdown) const {
    std::vector<std::size_t> widths(rows_.front().size(), 0);
    for (const auto& cells : rows_) {
      for (std::size_t i = 0; i < cells.size(); ++i) widths[i] = std::max(widths[i], cells[i].size());
    }
    for (std::size_t r = 0; r < rows_.size(); ++r) {
      std::string line;
      for (std::size_t i = 0; i < rows_[r].size(); ++i) {
        if (markdown) {
          line += "| " + rows_[r][i] + " ";
        } else {
          const bool last = i + 1 == rows_[r].size();
          line += last ? rows_[r][i] : fmt::format("{:<{}}  ", rows_[r][i], widths[i]);
        }
      }
      fmt::print("{}{}\n", line, markdown ? "|" : "");
      if (markdown && r == 0) {
        std::string rule;
        for (std::size_t i = 0; i < rows_[0].size(); ++i) rule += "|---";
        fmt::print("{}|\n", rule);
      }
    }
  }

 private:
  std::vector<std::vector<std::string>> rows_;
};

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

void print_uls_commands(bool markdown) {
  Table table({"mnemonic", "name", "cli name", "access", "values", "error", "while measuring", "section"});
  for (const auto& command : uls::command_table()) {
    table.add({std::string(command.mnemonic), std::string(command.title), std::string(command.cli_name),
               std::string(uls::access_name(command.access)), range_text(command),
               command.value_error == 0 ? "-" : std::to_string(command.value_error),
               command.rejected_while_measuring ? "error 31" : "accepted", std::string(command.reference)});
  }
  table.print(markdown);
}

void print_uls_errors(bool markdown) {
  Table table({"number", "explanation", "display", "group", "service"});
  for (const auto& error : uls::error_table()) {
    table.add({std::to_string(error.number), std::string(error.explanation), std::string(error.display),
               std::string(uls::error_group_name(error.group)), error.service_required ? "LTI" : "-"});
  }
  table.print(markdown);
}

void print_ls5_commands(bool markdown) {
  Table table({"code", "name", "cli name", "broadcast"});
  for (const auto& command : ls5::command_table()) {
    table.add({std::string(command.code), std::string(command.name), std::string(command.cli_name),
               command.broadcast_allowed ? "yes, no reply" : "no"});
  }
  table.print(markdown);
}

void print_ls5_parameters(bool markdown) {
  Table table({"address", "name", "cli name", "accepted", "default", "since"});
  for (const auto& parameter : ls5::parameter_table()) {
    std::string since = parameter.since == ls5::any_firmware ? "-" : parameter.since.to_string();
    if (parameter.ethernet_only) since += " (Ethernet)";
    table.add({ls5::hex_byte(parameter.address), std::string(parameter.name), std::string(parameter.cli_name),
               ls5::describe_accepted_values(parameter),
               parameter.default_source == ls5::DefaultSource::fixed ? ls5::hex_byte(parameter.default_value)
                                                                     : "from serial number",
               since});
  }
  table.print(markdown);
}

}  // namespace

void add_tables_command(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<TableOptions>();
  auto* command = app.add_subcommand("tables", "Print the protocol registries (commands, errors, parameters)");
  command->add_option("table", options->which, "uls-commands | uls-errors | ls5-commands | ls5-parameters")
      ->required()
      ->check(CLI::IsMember({"uls-commands", "uls-errors", "ls5-commands", "ls5-parameters"}));
  command->add_flag("--markdown", options->markdown, "Markdown table instead of plain columns");
  command->callback([options, &exit_code] {
    if (options->which == "uls-commands") print_uls_commands(options->markdown);
    if (options->which == "uls-errors") print_uls_errors(options->markdown);
    if (options->which == "ls5-commands") print_ls5_commands(options->markdown);
    if (options->which == "ls5-parameters") print_ls5_parameters(options->markdown);
    exit_code = exit_ok;
  });
}

}  // namespace rangekit::cli
