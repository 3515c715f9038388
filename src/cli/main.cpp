#include <fmt/core.h>

#include <exception>
#include <string>

#include "cli/commands.hpp"
#include "cli/sim.hpp"
#include "rangekit/version.hpp"

namespace {

// "rangekit ls5 frob" ends in CLI11's "A subcommand is required": say instead which
// word was not understood and what would have been (issue 11 point 5). Nothing
// printed when the error is of another kind.
bool reported_unknown_subcommand(CLI::App& app) {
  CLI::App* deepest = &app;
  std::string path = "rangekit";
  for (auto chosen = deepest->get_subcommands(); !chosen.empty(); chosen = deepest->get_subcommands()) {
    deepest = chosen.front();
    path += " " + deepest->get_name();
  }
  if (deepest->get_require_subcommand_min() == 0) return false;
  const auto leftover = deepest->remaining();
  if (leftover.empty() || leftover.front().empty() || leftover.front().front() == '-') return false;
  std::string known;
  for (const CLI::App* sub :
       deepest->get_subcommands([](CLI::App* candidate) { return !candidate->get_group().empty(); }))
    known += (known.empty() ? "" : ", ") + sub->get_name();
  fmt::print(stderr, "{}: unknown subcommand '{}' (one of: {}; {} --help)\n", path, leftover.front(), known, path);
  return true;
}

int run(int argc, char** argv) {
  CLI::App app{"rangekit: configure, stream and emulate ULS and LS5 laser distance sensors"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("rangekit ") + rangekit::version_string);
  int exit_code = rangekit::cli::exit_ok;
  rangekit::cli::add_demo_command(app, exit_code);
  rangekit::cli::add_decode_command(app, exit_code);
  rangekit::cli::add_tables_command(app, exit_code);
  rangekit::cli::add_sim_command(app, exit_code);
  rangekit::cli::add_uls_command(app, exit_code);
  rangekit::cli::add_ls5_command(app, exit_code);
  rangekit::cli::add_replay_command(app, exit_code);
  rangekit::cli::add_detect_command(app, exit_code);
  rangekit::cli::add_capture_command(app, exit_code);
  rangekit::cli::add_serve_command(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // --help and --version exit 0; every other parse error is a usage error (docs/cli.md).
    if (reported_unknown_subcommand(app)) return rangekit::cli::exit_usage;
    const int printed = app.exit(error);
    return printed == 0 ? rangekit::cli::exit_ok : rangekit::cli::exit_usage;
  }
  return exit_code;
}

}  // namespace

// Exceptions stop here: the library returns Result values, and anything else
// (out of memory, a bug) becomes one line on stderr and a non-zero exit.
int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& error) {
    std::fputs("rangekit: internal error: ", stderr);
    std::fputs(error.what(), stderr);
    std::fputs("\n", stderr);
  } catch (...) {
    std::fputs("rangekit: internal error\n", stderr);
  }
  return 70;  // EX_SOFTWARE
}
