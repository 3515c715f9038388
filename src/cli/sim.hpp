// `rangekit sim <family>`: the emulators. This part is shared by every family: the
// runtime options, signal handling and the ready line tests wait for.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "rangekit/sim/emulator_runtime.hpp"

namespace rangekit::cli {

struct SimCommonOptions {
  std::string control;     // --control PATH: JSON-lines Unix socket
  std::string state_dir;   // --state DIR: non-volatile memory
  std::string scene;       // --scene FILE (TOML)
  std::uint32_t seed = 1;  // --seed N
  double time_scale = 1;   // --time-scale X
  bool virtual_clock = false;
  std::string wire_log;  // --wire-log FILE
};

void add_common_sim_options(CLI::App& command, SimCommonOptions& options);

// Serves the lines until SIGINT/SIGTERM or {"cmd":"shutdown"}. Prints one
// "ready" line to stdout first (each line's name and path, and the control
// path), so scripts and tests can wait for it instead of sleeping. Device
// commands on the control socket go to `extension`.
int run_emulator(std::vector<LineConfig> lines, const SimCommonOptions& options, const std::string& title,
                 EmulatorRuntime::ControlExtension extension);

// The exit code of a --scene file that cannot be used, the same for every family:
// 4 when it cannot be read, else 3, input that does not
// decode (docs/cli.md, exit codes), whatever the scene loader's error code.
int scene_exit_code(const Error& error);

// Each family adds its own subcommand of `sim` (cli_family.hpp).
void add_sim_command(CLI::App& app, int& exit_code);
// `sim replay`: a recorded sensor (sim_replay.cpp).
void add_sim_replay_command(CLI::App& sim, int& exit_code);

}  // namespace rangekit::cli
