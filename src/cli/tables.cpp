// `rangekit tables`: the command, error and parameter registries as text or
// Markdown, straight from the tables the codecs use (so help and docs cannot
// drift from the code). Each family names its own (cli_family.hpp).
#include <string>
#include <vector>

#include "cli/cli_family.hpp"
#include "cli/commands.hpp"

namespace rangekit::cli {
namespace {

struct TableOptions {
  std::string which;
  bool markdown = false;
};

// "<family>-<table>", the word the command takes.
std::string table_word(const CliFamily& family, const CliTable& table) {
  return std::string(family.name) + "-" + std::string(table.name);
}

}  // namespace

void add_tables_command(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<TableOptions>();
  auto* command = app.add_subcommand("tables", "Print the protocol registries (commands, errors, parameters)");
  std::vector<std::string> words;
  for (const CliFamily* family : cli_families()) {
    for (const CliTable& table : family->tables) words.push_back(table_word(*family, table));
  }
  std::string help;
  for (const auto& word : words) help += (help.empty() ? "" : " | ") + word;
  command->add_option("table", options->which, help)->required()->check(CLI::IsMember(words));
  command->add_flag("--markdown", options->markdown, "Markdown table instead of plain columns");
  command->callback([options, &exit_code] {
    for (const CliFamily* family : cli_families()) {
      for (const CliTable& table : family->tables) {
        if (table_word(*family, table) == options->which) table.print(options->markdown);
      }
    }
    exit_code = exit_ok;
  });
}

}  // namespace rangekit::cli
