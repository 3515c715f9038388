// `rangekit sim ls5`: placeholder until the LS5 emulator lands (issue 5).
#include <fmt/core.h>

#include "cli/commands.hpp"
#include "cli/sim.hpp"

namespace rangekit::cli {
void add_sim_ls5(CLI::App& sim, int& exit_code) {
  auto* command = sim.add_subcommand("ls5", "LS5 emulator (not yet available)");
  command->callback([&exit_code] {
    fmt::print(stderr, "rangekit sim ls5: the LS5 emulator is not built yet\n");
    exit_code = exit_usage;
  });
}
}  // namespace rangekit::cli
