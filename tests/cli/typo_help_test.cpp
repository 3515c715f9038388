// A typo gets the fix, not a list to search (docs/cli.md, "Errors that point at the fix"), and
// every `--help` fits an 80-column terminal.
#include <gtest/gtest.h>

#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli/cli_run.hpp"

namespace {

using cli_test::contains;
using cli_test::run_cli;

TEST(Typos, ASettingNameGetsTheOneItMostLikelyMeant) {
  // Checked before the port is opened: no sensor needed.
  const auto uls = run_cli("uls set --port /nonexistent moed=binning");
  EXPECT_EQ(uls.exit_code, 2) << uls.output;
  EXPECT_TRUE(contains(uls.output, "unknown setting 'moed'; did you mean 'mode'?")) << uls.output;
  const auto ls5 = run_cli("ls5 set --port /nonexistent medain-points=7");
  EXPECT_EQ(ls5.exit_code, 2) << ls5.output;
  EXPECT_TRUE(contains(ls5.output, "'medain-points' is not an LS5 setting; did you mean 'median-points'?"))
      << ls5.output;
  // Nothing close: the names to choose from, as before.
  const auto far = run_cli("uls set --port /nonexistent frobnicate=1");
  EXPECT_TRUE(contains(far.output, "writable names: ")) << far.output;
}

TEST(Typos, AValueNameGetsItsAcceptedSpelling) {
  const auto run = run_cli("uls set --port /nonexistent mode=binnig");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_TRUE(contains(run.output, "did you mean 'binning'?")) << run.output;
  // The values as they are typed, with their §8 codes: "look-down", never "look down".
  EXPECT_TRUE(contains(run.output, "averaging (1), binning (2), look-down (3)")) << run.output;
}

TEST(Typos, AnOptionOrSubcommandGetsTheOneItMostLikelyMeant) {
  const auto option = run_cli("uls set --prot /dev/null mode=binning");
  EXPECT_EQ(option.exit_code, 2) << option.output;
  EXPECT_TRUE(contains(option.output, "unknown option '--prot'; did you mean '--port'?")) << option.output;
  const auto subcommand = run_cli("uls strem --port /dev/null");
  EXPECT_EQ(subcommand.exit_code, 2) << subcommand.output;
  EXPECT_TRUE(contains(subcommand.output, "unknown subcommand 'strem'; did you mean 'stream'?")) << subcommand.output;
}

// The subcommands a help text lists under "Subcommands:".
std::vector<std::string> subcommands_of(const std::string& help) {
  std::vector<std::string> names;
  std::istringstream lines(help);
  bool listing = false;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("Subcommands:", 0) == 0) {
      listing = true;
    } else if (listing && line.rfind("  ", 0) == 0 && line.size() > 2 && line[2] != ' ') {
      names.push_back(line.substr(2, line.find(' ', 2) - 2));
    } else if (listing && !line.empty() && line.front() != ' ') {
      listing = false;
    }
  }
  return names;
}

TEST(HelpWidth, EverySubcommandsHelpFitsEightyColumns) {
  std::vector<std::string> pending{""};
  std::set<std::string> seen;
  while (!pending.empty()) {
    const std::string command = pending.back();
    pending.pop_back();
    if (!seen.insert(command).second) continue;
    const auto help = run_cli(command + " --help");
    EXPECT_EQ(help.exit_code, 0) << command << ": " << help.output;
    std::istringstream lines(help.output);
    for (std::string line; std::getline(lines, line);) {
      // One word longer than the room left (a path) may not be broken.
      const bool one_word = line.find(' ', line.find_first_not_of(' ')) == std::string::npos;
      EXPECT_TRUE(line.size() <= 80 || one_word)
          << "rangekit " << command << " --help, " << line.size() << " columns:\n"
          << line;
    }
    for (const std::string& sub : subcommands_of(help.output)) pending.push_back(command + " " + sub);
  }
  EXPECT_GT(seen.size(), 30U);  // the walk reached the nested subcommands
}

}  // namespace
