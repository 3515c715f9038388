#include "cli/sim.hpp"

#include <fmt/core.h>

#include <atomic>
#include <csignal>

#include "cli/commands.hpp"

namespace rangekit::cli {
namespace {

std::atomic<bool> stop_requested{false};

extern "C" void request_stop(int /*signal*/) { stop_requested.store(true); }

void install_signal_handlers() {
  struct sigaction action {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  std::signal(SIGPIPE, SIG_IGN);
}

}  // namespace

void add_common_sim_options(CLI::App& command, SimCommonOptions& options) {
  command.add_option("--control", options.control, "Unix socket taking JSON-line commands (docs/emulators.md)");
  command.add_option("--state", options.state_dir, "directory for the non-volatile memory (default: none)");
  command.add_option("--scene", options.scene, "TOML scene file (docs/emulators.md)");
  command.add_option("--seed", options.seed, "seed for repeatable noise");
  command.add_option("--time-scale", options.time_scale, "run the clock X times faster than real time")
      ->check(in_range(0.001, 1000, "times real time"));
  command.add_flag("--virtual-clock", options.virtual_clock,
                   "time moves only on {\"cmd\":\"advance\"} from the control socket (for tests)");
}

int run_emulator(std::vector<LineConfig> lines, const SimCommonOptions& options, const std::string& title,
                 EmulatorRuntime::ControlExtension extension) {
  if (options.virtual_clock && options.control.empty()) {
    fmt::print(stderr, "rangekit sim: --virtual-clock needs --control (time only moves on request)\n");
    return exit_usage;
  }
  RuntimeOptions runtime_options;
  runtime_options.virtual_clock = options.virtual_clock;
  runtime_options.time_scale = options.time_scale;
  runtime_options.seed = options.seed;
  if (!options.control.empty()) runtime_options.control_path = options.control;
  auto runtime = EmulatorRuntime::create(std::move(lines), runtime_options);
  if (!runtime) {
    fmt::print(stderr, "rangekit sim: {}\n", runtime.error().message);
    return exit_io;
  }
  (*runtime)->set_control_extension(std::move(extension));
  install_signal_handlers();
  std::string ready = title + " ready:";
  for (std::size_t i = 0; i < (*runtime)->line_count(); ++i) ready += fmt::format(" {}", (*runtime)->line_path(i));
  if (!options.control.empty()) ready += " control " + options.control;
  fmt::print("{}\n", ready);
  std::fflush(stdout);
  auto served = (*runtime)->run(stop_requested);
  if (!served) {
    fmt::print(stderr, "rangekit sim: {}\n", served.error().message);
    return exit_io;
  }
  return exit_ok;  // the runtime's destructor removes the symlinks and the control socket
}

void add_sim_command(CLI::App& app, int& exit_code) {
  auto* sim = app.add_subcommand("sim", "Run an emulated sensor on pseudo-terminals (no hardware needed)");
  sim->require_subcommand(1);
  add_sim_uls(*sim, exit_code);
  add_sim_ls5(*sim, exit_code);
}

}  // namespace rangekit::cli
