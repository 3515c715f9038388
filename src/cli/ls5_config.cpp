// `rangekit ls5 config save|load|diff FILE`: placeholder until the TOML config lands.
#include "cli/commands.hpp"
#include "cli/ls5_cli.hpp"

namespace rangekit::cli {

void add_ls5_config_command(CLI::App& ls5, int& exit_code) {
  auto* config = ls5.add_subcommand("config", "save, load or diff all parameters as a readable TOML file");
  config->require_subcommand(1);
  (void)exit_code;
}

}  // namespace rangekit::cli
