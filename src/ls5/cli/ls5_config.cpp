// `rangekit ls5 config save|load|diff FILE`: every setting as readable TOML.
#include <fmt/core.h>

#include <memory>

#include "cli/commands.hpp"
#include "cli/config_diff.hpp"
#include "ls5/cli/ls5_cli.hpp"
#include "rangekit/ls5/host_config.hpp"

namespace rangekit::cli {
namespace {

struct ConfigCommand {
  Ls5Connection connection;
  std::string file;
};

// The same lines as `rangekit uls config diff` (docs/cli.md).
std::vector<DiffLine> diff_lines(const std::vector<ls5::ConfigDifference>& differences) {
  std::vector<DiffLine> lines;
  lines.reserve(differences.size());
  for (const auto& difference : differences)
    lines.push_back({std::string(difference.setting->name), difference.file_value, difference.device_value});
  return lines;
}

using Action = std::function<int(ls5::Driver&, const ConfigCommand&)>;

void add_config_subcommand(CLI::App& config, int& exit_code, const std::string& name, const std::string& help,
                           const Action& action) {
  auto state = std::make_shared<ConfigCommand>();
  auto* command = config.add_subcommand(name, help);
  add_ls5_connection_options(*command, state->connection);
  command->add_option("file", state->file, "TOML file")->required();
  command->callback([&exit_code, state, action, name] {
    auto driver = open_ls5_driver(state->connection);
    if (!driver) {
      exit_code = report_ls5_failure("config " + name, driver.error(), state->connection);
      return;
    }
    exit_code = action(**driver, *state);
  });
}

}  // namespace

void add_ls5_config_command(CLI::App& ls5, int& exit_code) {
  auto* config = ls5.add_subcommand("config", "save, load or diff all parameters as a readable TOML file");
  config->require_subcommand(1);

  add_config_subcommand(*config, exit_code, "save", "read every parameter and write them to FILE",
                        [](ls5::Driver& driver, const ConfigCommand& command) {
                          auto read = ls5::read_device_config(driver);
                          if (!read) return report_ls5_failure("config save", read.error(), command.connection);
                          Status saved = ls5::save_config_file(*read, command.file);
                          if (!saved) {
                            fmt::print(stderr, "rangekit ls5 config save: {}\n", saved.error().message);
                            return exit_write_failed;
                          }
                          fmt::print("{} settings saved to {}\n", read->entries.size(), command.file);
                          return exit_ok;
                        });

  add_config_subcommand(*config, exit_code, "load", "upload FILE's [parameters], read every value back and verify it",
                        [](ls5::Driver& driver, const ConfigCommand& command) {
                          auto file = ls5::load_config_file(command.file);
                          if (!file) {
                            fmt::print(stderr, "rangekit ls5 config load: {}\n", file.error().message);
                            return file.error().code == Errc::io ? exit_io : exit_bad_input;
                          }
                          auto report = ls5::upload_config(driver, *file);
                          if (!report) return report_ls5_failure("config load", report.error(), command.connection);
                          for (const auto& skipped : report->skipped) fmt::print("skipped {}\n", skipped);
                          fmt::print("{} settings written\n", report->written.size());
                          if (!report->mismatches.empty()) {
                            fmt::print(stderr, "rangekit ls5 config load: {} settings read back differently:\n",
                                       report->mismatches.size());
                            print_diff_lines(diff_lines(report->mismatches));
                            return exit_device_error;
                          }
                          fmt::print("verified: every value reads back as in {}\n", command.file);
                          return exit_ok;
                        });

  add_config_subcommand(*config, exit_code, "diff", "compare FILE with the sensor (exit 0 when equal, 1 when not)",
                        [](ls5::Driver& driver, const ConfigCommand& command) {
                          auto file = ls5::load_config_file(command.file);
                          if (!file) {
                            fmt::print(stderr, "rangekit ls5 config diff: {}\n", file.error().message);
                            return file.error().code == Errc::io ? exit_io : exit_bad_input;
                          }
                          auto differences = ls5::diff_config(driver, *file);
                          if (!differences) {
                            return report_ls5_failure("config diff", differences.error(), command.connection);
                          }
                          return print_config_diff(diff_lines(*differences), file->entries.size());
                        });
}

}  // namespace rangekit::cli
