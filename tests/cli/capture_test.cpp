// `rangekit capture` end to end: a ULS and an LS5 emulator on ptys streamed
// into one SQLite file that `replay` reads back.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli/cli_run.hpp"
#include "ls5_driver/cli_process.hpp"

namespace {

using ls5_driver_test::Child;
using ls5_driver_test::run_cli;

using cli_test::contains;

TEST(Capture, BothFamiliesIntoOneFileThatReplays) {
  const ls5_driver_test::TempDir temp;
  const std::filesystem::path& dir = temp.path;
  const auto uls_config = (dir / "uls-config").string();
  const auto ls5_port = (dir / "ls5").string();
  const auto file = (dir / "both.sqlite").string();
  std::string captured_err;
  {
    Child uls({"sim", "uls", "--port", (dir / "uls").string(), "--config-port", uls_config});
    ASSERT_TRUE(contains(uls.read_line(), "ready:"));
    Child ls5({"sim", "ls5", "--port", ls5_port});
    ASSERT_TRUE(contains(ls5.read_line(), "ready:"));

    const auto run = run_cli(dir, {"capture", "--out", file, "--uls", uls_config, "--ls5", ls5_port, "--ls5-thinning",
                                   "10", "--duration", "3"});
    ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;  // without --echo only the file gets the data
    captured_err = run.err;
  }
  const auto replay = run_cli(dir, {"replay", file, "--full-speed", "--format", "jsonl"});
  EXPECT_EQ(replay.exit_code, 0) << replay.err;
  EXPECT_TRUE(contains(replay.out, R"("device":"uls")")) << replay.out;
  EXPECT_TRUE(contains(replay.out, R"("device":"ls5")")) << replay.out;
  // "`capture` ends with "N samples → FILE; replay with …"", and N is
  // what the file holds: one replayed line per sample.
  const std::string closing = " \u2192 " + file + "; replay with: rangekit replay " + file;
  ASSERT_TRUE(contains(captured_err, closing)) << captured_err;
  // Each sensor is named: its connect, and its share of the samples.
  EXPECT_TRUE(contains(captured_err, "connected: " + uls_config)) << captured_err;
  EXPECT_TRUE(contains(captured_err, "connected: " + ls5_port)) << captured_err;
  ASSERT_NE(captured_err.rfind(" samples ("), std::string::npos) << captured_err;
  const std::string shares = captured_err.substr(captured_err.rfind(" samples ("));
  EXPECT_TRUE(contains(shares, "uls " + uls_config + " ")) << captured_err;
  EXPECT_TRUE(contains(shares, "ls5 " + ls5_port + " ")) << captured_err;
  const auto said = captured_err.rfind("rangekit capture: ", captured_err.find(closing));
  ASSERT_NE(said, std::string::npos) << captured_err;
  const auto count = std::stoull(captured_err.substr(said + std::string("rangekit capture: ").size()));
  std::size_t replayed = 0;
  for (auto at = replay.out.find("\"device\":"); at != std::string::npos; at = replay.out.find("\"device\":", at + 1))
    ++replayed;
  EXPECT_GT(count, 0U);
  EXPECT_EQ(replayed, count);

  const auto nothing = run_cli(dir, {"capture", "--out", file});
  EXPECT_EQ(nothing.exit_code, 2) << nothing.err;
  const auto absent = run_cli(dir, {"capture", "--out", file, "--uls", (dir / "absent").string()});
  EXPECT_EQ(absent.exit_code, 4) << absent.err;
  EXPECT_TRUE(contains(absent.err, "absent")) << absent.err;
}

// The closing line points at a file to replay; when the file cannot be made there is none.
TEST(Capture, AFileThatCannotBeOpenedGetsNoReplayHint) {
  const ls5_driver_test::TempDir temp;
  const auto ls5_port = (temp.path / "ls5").string();
  Child ls5({"sim", "ls5", "--port", ls5_port});
  ASSERT_TRUE(contains(ls5.read_line(), "ready:"));
  const auto file = (temp.path / "no-such-dir" / "x.sqlite").string();
  const auto run = run_cli(temp.path, {"capture", "--out", file, "--ls5", ls5_port, "--duration", "1"});
  EXPECT_EQ(run.exit_code, 4) << run.err;
  EXPECT_TRUE(contains(run.err, "no-such-dir")) << run.err;
  EXPECT_FALSE(contains(run.err, "replay with")) << run.err;
}

}  // namespace
