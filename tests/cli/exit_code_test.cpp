// One error-to-exit-code table for both families (docs/cli.md, "Exit codes" and
// "Which error gives which code"). Each case runs the built
// binary for the ULS and the LS5 and expects the same code, typed from the table.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli/cli_run.hpp"

namespace {

using cli_test::CliResult;
using cli_test::count_of;
using cli_test::run_cli;

class ExitCodes : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("rangekit-exit-codes-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    std::ofstream(dir_ / "plain-file") << "not a terminal\n";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

// docs/cli.md: "4 | a file or port cannot be opened or read". A regular file is a port
// that cannot be opened as a terminal (Errc::unsupported inside): the ULS said 4, the
// LS5 said 2. Both say 4 now.
TEST_F(ExitCodes, APortThatIsNotATerminalIsExit4ForBothFamilies) {
  const std::string port = (dir_ / "plain-file").string();
  const CliResult uls = run_cli("uls info --port " + port);
  const CliResult ls5 = run_cli("ls5 info --port " + port);
  EXPECT_EQ(uls.exit_code, 4) << uls.output;
  EXPECT_EQ(ls5.exit_code, 4) << ls5.output;
  EXPECT_NE(uls.output.find("is not a serial port or terminal"), std::string::npos) << uls.output;
  EXPECT_NE(ls5.output.find("is not a serial port or terminal"), std::string::npos) << ls5.output;
}

TEST_F(ExitCodes, AMissingPortIsExit4ForEveryCommandThatOpensOne) {
  const std::string port = (dir_ / "nothing-here").string();
  const std::vector<std::string> commands{"uls info --port ", "ls5 info --port ",
                                          "capture --out " + (dir_ / "c.sqlite").string() + " --uls ",
                                          "capture --out " + (dir_ / "d.sqlite").string() + " --ls5 "};
  for (const std::string& command : commands) {
    const CliResult run = run_cli(command + port);
    EXPECT_EQ(run.exit_code, 4) << command << ": " << run.output;
  }
}

// "Errors are not wrapped twice ("cannot open X: cannot open serial port X")".
TEST_F(ExitCodes, ThePortIsNamedOnceWhenItCannotBeOpened) {
  const std::string port = (dir_ / "nothing-here").string();
  const std::vector<std::string> commands{"uls info --port ", "ls5 info --port ", "uls stream --port ",
                                          "capture --out " + (dir_ / "e.sqlite").string() + " --uls "};
  for (const std::string& command : commands) {
    const CliResult run = run_cli(command + port);
    EXPECT_EQ(count_of(run.output, port), 1U) << run.output;
    EXPECT_EQ(count_of(run.output, "cannot open"), 1U) << run.output;
    EXPECT_EQ(count_of(run.output, "I/O error"), 0U) << "no category word before the message: " << run.output;
  }
}

}  // namespace
