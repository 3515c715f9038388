// The LS5's registries for `rangekit tables`: its commands (table 9.1) and parameters (table 9.3).
#include <array>
#include <string>

#include "cli/text_table.hpp"
#include "ls5/cli/ls5_cli.hpp"
#include "rangekit/ls5/commands.hpp"
#include "rangekit/ls5/parameters.hpp"

namespace rangekit::cli {
namespace {

void print_commands(bool markdown) {
  TextTable table({"code", "name", "cli name", "broadcast"});
  for (const auto& command : ls5::command_table()) {
    table.add({std::string(command.code), std::string(command.name), std::string(command.cli_name),
               command.broadcast_allowed ? "yes, no reply" : "no"});
  }
  table.print(markdown);
}

void print_parameters(bool markdown) {
  TextTable table({"address", "name", "cli name", "accepted", "default", "since"});
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

constexpr std::array tables{CliTable{"commands", print_commands}, CliTable{"parameters", print_parameters}};

}  // namespace

const std::span<const CliTable> ls5_tables{tables};

}  // namespace rangekit::cli
