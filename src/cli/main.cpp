#include <fmt/core.h>

#include <algorithm>
#include <exception>
#include <string>
#include <vector>

#include "cli/cli_family.hpp"
#include "cli/commands.hpp"
#include "cli/help_width.hpp"
#include "cli/sim.hpp"
#include "rangekit/core/text.hpp"
#include "rangekit/version.hpp"

namespace {

// The subcommands chosen, outermost first, and their words ("rangekit sim <family>").
std::vector<CLI::App*> chosen_chain(CLI::App& app, std::string& path) {
  std::vector<CLI::App*> chain{&app};
  path = "rangekit";
  for (auto chosen = app.get_subcommands(); !chosen.empty(); chosen = chain.back()->get_subcommands()) {
    chain.push_back(chosen.front());
    path += " " + chain.back()->get_name();
  }
  return chain;
}

// "; did you mean 'x'?" when a known word is that close to the typed one, else "".
std::string did_you_mean(std::string_view typed, const std::vector<std::string>& known) {
  const auto meant = rangekit::text::closest(typed, known);
  return meant ? "; did you mean '" + *meant + "'?" : "";
}

// "rangekit sim frob" ends in CLI11's "A subcommand is required": say instead which word was
// not understood and what would have been. Nothing printed for an error of another kind.
bool reported_unknown_subcommand(CLI::App& app) {
  std::string path;
  CLI::App* deepest = chosen_chain(app, path).back();
  if (deepest->get_require_subcommand_min() == 0) return false;
  const auto leftover = deepest->remaining();
  if (leftover.empty() || leftover.front().empty() || leftover.front().front() == '-') return false;
  std::string known;
  std::vector<std::string> names;
  for (const CLI::App* sub :
       deepest->get_subcommands([](CLI::App* candidate) { return !candidate->get_group().empty(); })) {
    known += (known.empty() ? "" : ", ") + sub->get_name();
    names.push_back(sub->get_name());
  }
  fmt::print(stderr, "{}: unknown subcommand '{}'{} (one of: {}; {} --help)\n", path, leftover.front(),
             did_you_mean(leftover.front(), names), known, path);
  return true;
}

// "--prot" ends in "--port is required" or "arguments were not expected": say which option was
// not understood, and the one it most likely meant.
bool reported_unknown_option(CLI::App& app) {
  std::string path;
  const std::vector<CLI::App*> chain = chosen_chain(app, path);
  std::vector<std::string> known;
  for (const CLI::App* command : chain) {
    for (const CLI::Option* option : command->get_options()) {
      for (const std::string& name : option->get_lnames()) known.push_back("--" + name);
    }
  }
  for (const std::string& word : chain.back()->remaining()) {
    if (word.size() < 3 || word.rfind("--", 0) != 0) continue;
    const std::string name = word.substr(0, word.find('='));
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    fmt::print(stderr, "{}: unknown option '{}'{} ({} --help)\n", path, name, did_you_mean(name, known), path);
    return true;
  }
  return false;
}

int run(int argc, char** argv) {
  CLI::App app{"rangekit: configure, stream and emulate " + rangekit::cli::cli_family_labels(" and ") +
               " laser distance sensors"};
  app.formatter(std::make_shared<rangekit::cli::WrappingFormatter>());  // before the subcommands: they copy it
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("rangekit ") + rangekit::version_string);
  int exit_code = rangekit::cli::exit_ok;
  rangekit::cli::add_demo_command(app, exit_code);
  rangekit::cli::add_decode_command(app, exit_code);
  rangekit::cli::add_tap_command(app, exit_code);
  rangekit::cli::add_tables_command(app, exit_code);
  rangekit::cli::add_sim_command(app, exit_code);
  for (const rangekit::cli::CliFamily* family : rangekit::cli::cli_families()) family->add_command(app, exit_code);
  rangekit::cli::add_replay_command(app, exit_code);
  rangekit::cli::add_detect_command(app, exit_code);
  rangekit::cli::add_capture_command(app, exit_code);
  rangekit::cli::add_serve_command(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // --help and --version exit 0; every other parse error is a usage error (docs/cli.md).
    if (reported_unknown_subcommand(app) || reported_unknown_option(app)) return rangekit::cli::exit_usage;
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
