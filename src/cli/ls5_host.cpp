// Placeholder while the host side of issue 6 is written; replaced by the real subcommand.
#include <fmt/core.h>

#include "cli/commands.hpp"

namespace rangekit::cli {

void add_ls5_command(CLI::App& app, int& exit_code) {
  auto* command = app.add_subcommand("ls5", "(not yet available)");
  command->callback([&exit_code] {
    fmt::print(stderr, "rangekit ls5: not yet available\n");
    exit_code = 70;
  });
}

}  // namespace rangekit::cli
