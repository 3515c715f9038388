// `rangekit sim uls`: placeholder until the ULS emulator lands (issue 4).
#include <fmt/core.h>

#include "cli/commands.hpp"
#include "cli/sim.hpp"

namespace rangekit::cli {
void add_sim_uls(CLI::App& sim, int& exit_code) {
  auto* command = sim.add_subcommand("uls", "ULS emulator (not yet available)");
  command->callback([&exit_code] {
    fmt::print(stderr, "rangekit sim uls: the ULS emulator is not built yet\n");
    exit_code = exit_usage;
  });
}
}  // namespace rangekit::cli
