// The man page, the bash completion and docs/cli.md name every command the
// binary has (and the family subcommands), so the packaged help cannot drift
// from `rangekit --help`.
#include <gtest/gtest.h>
#include "build_paths.hpp"

#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "ls5_driver/cli_process.hpp"

namespace {

using ls5_driver_test::read_file;
using ls5_driver_test::run_cli;
using ls5_driver_test::TempDir;

const std::string root = rangekit::test::source_dir();

// The names under "Subcommands:" in CLI11's help text.
std::set<std::string> subcommands_in_help(const std::vector<std::string>& arguments) {
  TempDir dir;
  const auto run = run_cli(dir.path, arguments);
  std::set<std::string> names;
  std::istringstream lines(run.out);
  std::string line;
  bool in_list = false;
  while (std::getline(lines, line)) {
    if (line.rfind("Subcommands:", 0) == 0 || line.rfind("SUBCOMMANDS:", 0) == 0) {
      in_list = true;
      continue;
    }
    std::smatch name;
    if (in_list && std::regex_search(line, name, std::regex(R"(^  ([a-z0-9-]+))"))) names.insert(name[1]);
  }
  return names;
}

// The words of `local NAME="..."` in the completion script.
std::set<std::string> completion_words(const std::string& variable) {
  const std::string script = read_file(root + "/packaging/rangekit.bash-completion");
  std::smatch list;
  std::set<std::string> words;
  if (!std::regex_search(script, list, std::regex("local " + variable + "=\"([^\"]*)\""))) return words;
  std::istringstream in(list[1].str());
  for (std::string word; in >> word;) words.insert(word);
  return words;
}

TEST(Packaging, CompletionManPageAndDocsNameEveryCommand) {
  const auto commands = subcommands_in_help({"--help"});
  ASSERT_GE(commands.size(), 9u);
  EXPECT_EQ(completion_words("commands"), commands);
  const std::string man = read_file(root + "/packaging/rangekit.1");
  const std::string docs = read_file(root + "/docs/cli.md");
  for (const auto& command : commands) {
    EXPECT_NE(man.find(".B " + command), std::string::npos) << "man page lacks " << command;
    EXPECT_NE(docs.find("`rangekit " + command), std::string::npos) << "docs/cli.md lacks " << command;
  }
}

TEST(Packaging, CompletionKnowsEveryFamilySubcommand) {
  for (const std::string family : {"uls", "ls5", "sim"}) {  // decode and tables take a positional
    const auto subcommands = subcommands_in_help({family, "--help"});
    ASSERT_FALSE(subcommands.empty()) << family;
    EXPECT_EQ(completion_words(family + "_commands"), subcommands) << family;
  }
}

}  // namespace
