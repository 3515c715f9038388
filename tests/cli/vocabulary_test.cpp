// One CLI vocabulary for both families: the same words and the same messages from
// `rangekit uls` and `rangekit ls5`. Expectations typed from docs/cli.md.
#include <gtest/gtest.h>
#include "build_paths.hpp"

#include <filesystem>
#include <regex>
#include <string>

#include "cli/cli_run.hpp"
#include "ls5_driver/cli_process.hpp"

namespace {

using cli_test::contains;
using cli_test::run_cli;

// "\"unknown subcommand\" for an unknown subcommand", at every level, naming the word
// and the subcommands there are; exit 2 ("usage error (unknown subcommand ...)", docs/cli.md).
TEST(Vocabulary, AnUnknownSubcommandIsNamedAtEveryLevel) {
  const auto top = run_cli("frobnicate");
  EXPECT_EQ(top.exit_code, 2) << top.output;
  EXPECT_TRUE(contains(top.output, "rangekit: unknown subcommand 'frobnicate'")) << top.output;
  EXPECT_TRUE(contains(top.output, "capture")) << top.output;

  const auto uls = run_cli("uls frobnicate");
  EXPECT_EQ(uls.exit_code, 2) << uls.output;
  EXPECT_TRUE(contains(uls.output, "rangekit uls: unknown subcommand 'frobnicate'")) << uls.output;
  EXPECT_TRUE(contains(uls.output, "info")) << uls.output;

  const auto ls5 = run_cli("ls5 frobnicate --port /dev/null");
  EXPECT_EQ(ls5.exit_code, 2) << ls5.output;
  EXPECT_TRUE(contains(ls5.output, "rangekit ls5: unknown subcommand 'frobnicate'")) << ls5.output;

  const auto config = run_cli("uls config frobnicate");
  EXPECT_EQ(config.exit_code, 2) << config.output;
  EXPECT_TRUE(contains(config.output, "rangekit uls config: unknown subcommand 'frobnicate' (one of: save, load, diff"))
      << config.output;

  const auto sim = run_cli("sim frobnicate");
  EXPECT_TRUE(contains(sim.output, "rangekit sim: unknown subcommand 'frobnicate'")) << sim.output;
}

// "The same option and verb names: `--timeout`, `start/stop`, `reset`, `--no-reconnect`."
TEST(Vocabulary, BothFamiliesOfferTheSameVerbsAndOptions) {
  for (const std::string& family : {std::string("uls"), std::string("ls5")}) {
    const auto verbs = run_cli(family + " --help");
    for (const char* verb : {"start", "stop", "reset", "stream", "info", "get", "set", "save", "config"})
      EXPECT_TRUE(contains(verbs.output, std::string("\n  ") + verb + " ")) << family << " lacks " << verb;
    EXPECT_TRUE(contains(run_cli(family + " info --help").output, "--timeout")) << family;
    EXPECT_TRUE(contains(run_cli(family + " stream --help").output, "--no-reconnect")) << family;
  }
  EXPECT_TRUE(contains(run_cli("detect --help").output, "--timeout")) << "detect";
}

// The LS5's earlier words stay accepted, unlisted, so that scripts do not break.
TEST(Vocabulary, TheLs5sEarlierSpellingsStillWorkButAreNotListed) {
  const auto listed = run_cli("ls5 --help").output;
  for (const char* old_verb : {"on", "off", "defaults"}) {
    EXPECT_FALSE(contains(listed, std::string("\n  ") + old_verb + " ")) << old_verb;
    // Parsed as a subcommand: it gets as far as opening the port (exit 4, docs/cli.md).
    const auto run = run_cli(std::string("ls5 ") + old_verb + " --port /dev/null --timeout-ms 100");
    EXPECT_EQ(run.exit_code, 4) << old_verb << ": " << run.output;
  }
  EXPECT_FALSE(contains(run_cli("ls5 info --help").output, "--timeout-ms"));
  EXPECT_EQ(run_cli("detect --port /dev/null --timeout-ms 100").exit_code, 4);
}

// "`--json` for `info`, `get` and `detect`": one JSON object with the names and values of
// the NAME=VALUE lines, for both families.
TEST(Vocabulary, InfoAndGetPrintOneJsonObjectWithJson) {
  const ls5_driver_test::TempDir dir;
  const std::string uls_port = (dir.path / "uls").string();
  const std::string ls5_port = (dir.path / "ls5").string();
  ls5_driver_test::Child uls({"sim", "uls", "--port", uls_port});
  ASSERT_TRUE(contains(uls.read_line(), "ready:"));
  ls5_driver_test::Child ls5({"sim", "ls5", "--port", ls5_port});
  ASSERT_TRUE(contains(ls5.read_line(), "ready:"));

  const auto uls_info = run_cli("uls info --json --port " + uls_port);
  EXPECT_EQ(uls_info.exit_code, 0) << uls_info.output;
  EXPECT_EQ(uls_info.output.front(), '{') << uls_info.output;
  EXPECT_EQ(cli_test::count_of(uls_info.output, "\n"), 1U) << uls_info.output;
  EXPECT_TRUE(contains(uls_info.output, "\"port\":\"" + uls_port + "\"")) << uls_info.output;
  EXPECT_TRUE(contains(uls_info.output, "\"version\":")) << uls_info.output;

  const auto uls_get = run_cli("uls get --json --port " + uls_port + " prf");
  EXPECT_EQ(uls_get.exit_code, 0) << uls_get.output;
  EXPECT_EQ(uls_get.output.front(), '{') << uls_get.output;
  EXPECT_TRUE(contains(uls_get.output, "\"prf-hz\":")) << uls_get.output;
  EXPECT_FALSE(contains(uls_get.output, "#")) << "no wire comment in JSON: " << uls_get.output;

  const auto ls5_info = run_cli("ls5 info --json --port " + ls5_port);
  EXPECT_EQ(ls5_info.exit_code, 0) << ls5_info.output;
  EXPECT_EQ(ls5_info.output.front(), '{') << ls5_info.output;
  EXPECT_TRUE(contains(ls5_info.output, "\"address\":1")) << ls5_info.output;
  EXPECT_TRUE(contains(ls5_info.output, "\"range-mm\":")) << ls5_info.output;

  // Table 9.2: median filter points, default 5.
  const auto ls5_get = run_cli("ls5 get --json --port " + ls5_port + " median-points");
  EXPECT_EQ(ls5_get.exit_code, 0) << ls5_get.output;
  EXPECT_EQ(ls5_get.output, "{\"median-points\":5}\n");  // numbers as numbers
}

// "`sim --help` points to docs that exist": every docs/NAME.md a help text names is a file.
TEST(Vocabulary, HelpNamesOnlyDocsThatExist) {
  const std::regex doc_path(R"(docs/[A-Za-z0-9_-]+\.md)");
  std::size_t named = 0;
  for (const char* command : {"--help", "sim --help", "sim uls --help", "sim ls5 --help", "uls --help", "ls5 --help",
                              "capture --help", "detect --help", "replay --help", "decode --help", "demo --help"}) {
    const auto help = run_cli(command).output;
    for (std::sregex_iterator it(help.begin(), help.end(), doc_path), end; it != end; ++it) {
      ++named;
      EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(rangekit::test::source_dir()) / it->str()))
          << command << " names " << it->str();
    }
  }
  EXPECT_GT(named, 0U) << "sim's --control and --scene name their docs";
}

}  // namespace
