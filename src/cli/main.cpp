#include <fmt/core.h>

#include "cli/commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"rangekit: configure, stream and emulate ULS and LS5 laser distance sensors"};
  app.require_subcommand(1);
  int exit_code = rangekit::cli::exit_ok;
  rangekit::cli::add_demo_command(app, exit_code);
  rangekit::cli::add_decode_command(app, exit_code);
  rangekit::cli::add_tables_command(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // --help and --version exit 0; every other parse error is a usage error (docs/cli.md).
    const int printed = app.exit(error);
    return printed == 0 ? rangekit::cli::exit_ok : rangekit::cli::exit_usage;
  }
  return exit_code;
}
