#include <fmt/core.h>
#include <CLI/CLI.hpp>

int main(int argc, char** argv) {
  CLI::App app{"rangekit: toolkit for ULS and LS5 laser distance sensors"};
  app.require_subcommand(0, 1);
  CLI11_PARSE(app, argc, argv);
  return 0;
}
