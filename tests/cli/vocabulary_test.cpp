// Issue 11 point 5, "One CLI vocabulary for both families": the same words and the
// same messages from `rangekit uls` and `rangekit ls5`. Expectations typed from the
// issue and docs/cli.md.
#include <gtest/gtest.h>

#include <string>

#include "cli/cli_run.hpp"

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

}  // namespace
