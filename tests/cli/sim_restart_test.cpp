// `sim` restarts over a stale link left by `kill -9` of an earlier emulator, which could
// not remove its pty symlink or control socket: the next one on the same paths starts
// anyway and says what it removed.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli/cli_run.hpp"
#include "ls5_driver/cli_process.hpp"

namespace {

using cli_test::contains;
using ls5_driver_test::Child;
using ls5_driver_test::TempDir;

TEST(SimRestart, StartsOverTheLinkAndSocketOfAKilledEmulator) {
  for (const std::string& family : {std::string("uls"), std::string("ls5")}) {
    TempDir dir;
    const std::string port = (dir.path / family).string();
    const std::string control = (dir.path / (family + ".control")).string();
    {
      Child first({"sim", family, "--port", port, "--control", control});
      ASSERT_TRUE(contains(first.read_line(), "ready:")) << family;
      first.kill_hard();
    }
    ASSERT_TRUE(std::filesystem::is_symlink(port)) << "kill -9 leaves the link behind";
    Child second({"sim", family, "--port", port, "--control", control});
    EXPECT_TRUE(contains(second.read_line(), "ready: " + port)) << family;
    second.terminate();
    EXPECT_EQ(second.wait(), 0) << family;
    EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(port))) << "the second cleans up on exit";
  }
}

// A link to something that is still there is not touched: "already exists" as before.
TEST(SimRestart, KeepsALinkThatIsNotStale) {
  TempDir dir;
  const std::string port = (dir.path / "uls").string();
  std::filesystem::create_symlink("/dev/null", port);
  const auto run = cli_test::run_cli("sim uls --port " + port);
  EXPECT_EQ(run.exit_code, 4) << run.output;
  EXPECT_TRUE(contains(run.output, "already exists")) << run.output;
  EXPECT_EQ(std::filesystem::read_symlink(port), "/dev/null");
}

}  // namespace
