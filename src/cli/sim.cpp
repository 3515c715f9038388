#include "cli/sim.hpp"

#include <fmt/core.h>

#include <pthread.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <thread>

#include "cli/cli_family.hpp"
#include "cli/commands.hpp"
#include "rangekit/sim/pty.hpp"

namespace rangekit::cli {
namespace {

std::atomic<bool> stop_requested{false};

// SIGINT and SIGTERM are taken by a thread of their own in sigwait(), not by a handler: under
// ThreadSanitizer, which defers a handler to a safe point, an emulator once never ran its
// handler and served on. The runtime sees the flag within its poll timeout.
void install_signal_handlers() {
  std::signal(SIGPIPE, SIG_IGN);
  sigset_t stops;
  sigemptyset(&stops);
  sigaddset(&stops, SIGINT);
  sigaddset(&stops, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stops, nullptr);  // before any other thread: each inherits the mask
  std::thread([stops] {
    int taken = 0;
    sigwait(&stops, &taken);
    stop_requested.store(true);
  }).detach();
}

// An emulator killed with kill -9 leaves its pty symlink (pointing at a /dev/pts
// entry that went with it, or that a newer pty reuses) and its control socket (that
// nobody listens on) behind. Those are removed, said once on stderr, so the next `sim`
// starts; a link to a live pty, or a socket that still answers, is left for the
// runtime to refuse.
void remove_if_stale_link(const std::string& path) {
  if (PseudoTerminal::link_is_stale(path) && ::unlink(path.c_str()) == 0)
    fmt::print(stderr,
               "rangekit sim: removed the stale link {} (its pty is gone or belongs to another program now; an earlier "
               "emulator was killed)\n",
               path);
}

void remove_if_stale_socket(const std::string& path) {
  struct stat existing {};
  if (::lstat(path.c_str(), &existing) != 0 || !S_ISSOCK(existing.st_mode)) return;
  sockaddr_un address{};
  if (path.size() >= sizeof address.sun_path) return;
  address.sun_family = AF_UNIX;
  std::memcpy(address.sun_path, path.c_str(), path.size());
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return;
  const bool refused =
      ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0 && errno == ECONNREFUSED;
  ::close(fd);
  if (refused && ::unlink(path.c_str()) == 0)
    fmt::print(stderr,
               "rangekit sim: removed the stale control socket {} (nobody listens; an earlier emulator was killed)\n",
               path);
}

// Each family's emulator document: "docs/emulator-<name>.md, ...".
std::string emulator_docs() {
  std::string docs;
  for (const CliFamily* family : cli_families()) {
    docs += (docs.empty() ? "docs/emulator-" : ", docs/emulator-") + std::string(family->name) + ".md";
  }
  return docs;
}

}  // namespace

void add_common_sim_options(CLI::App& command, SimCommonOptions& options) {
  command.add_option("--control", options.control, "Unix socket taking JSON-line commands (" + emulator_docs() + ")");
  command.add_option("--state", options.state_dir, "directory for the non-volatile memory (default: none)");
  command.add_option("--scene", options.scene, "TOML scene file (" + emulator_docs() + ")");
  command.add_option("--seed", options.seed, "seed for repeatable noise");
  command.add_option("--time-scale", options.time_scale, "run the clock X times faster than real time")
      ->check(in_range(0.001, 1000, "times real time"));
  command.add_flag("--virtual-clock", options.virtual_clock,
                   "time moves only on {\"cmd\":\"advance\"} from the control socket (for tests)");
  command.add_option("--wire-log", options.wire_log,
                     "write every byte sent to the host, before line noise, to FILE (for benchmarks)");
}

int scene_exit_code(const Error& error) { return error.code == Errc::io ? exit_io : exit_bad_input; }

int run_emulator(std::vector<LineConfig> lines, const SimCommonOptions& options, const std::string& title,
                 EmulatorRuntime::ControlExtension extension) {
  if (options.virtual_clock && options.control.empty()) {
    fmt::print(stderr, "rangekit sim: --virtual-clock needs --control (time only moves on request)\n");
    return exit_usage;
  }
  install_signal_handlers();
  for (const LineConfig& line : lines)
    if (line.link_path) remove_if_stale_link(*line.link_path);
  if (!options.control.empty()) remove_if_stale_socket(options.control);
  RuntimeOptions runtime_options;
  runtime_options.virtual_clock = options.virtual_clock;
  runtime_options.time_scale = options.time_scale;
  runtime_options.seed = options.seed;
  if (!options.control.empty()) runtime_options.control_path = options.control;
  if (!options.wire_log.empty()) runtime_options.wire_log_path = options.wire_log;
  auto runtime = EmulatorRuntime::create(std::move(lines), runtime_options);
  if (!runtime) {
    fmt::print(stderr, "rangekit sim: {}\n", runtime.error().message);
    return exit_io;
  }
  (*runtime)->set_control_extension(std::move(extension));
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
  for (const CliFamily* family : cli_families()) family->add_sim_command(*sim, exit_code);
  add_sim_replay_command(*sim, exit_code);
}

}  // namespace rangekit::cli
