// `rangekit detect` tells a USB serial adapter's latency timer, read from sysfs: here a folder
// laid out like /sys/bus/usb-serial (RANGEKIT_SYSFS_ROOT) for the tty a pty's path resolves to.
#include <gtest/gtest.h>
#include "build_paths.hpp"

#include <filesystem>
#include <fstream>
#include <string>

#include "cli/cli_run.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/sim/pty.hpp"

namespace {

using cli_test::contains;
using ls5_driver_test::Child;
using ls5_driver_test::TempDir;

// A sysfs under `dir` where the tty behind `port` is an adapter with this timer; the folder.
std::string fake_sysfs(const TempDir& dir, const std::string& port, const std::string& timer) {
  const auto tty = std::filesystem::canonical(port).filename();
  const auto device = dir.path / "sys" / "bus" / "usb-serial" / "devices" / tty;
  std::filesystem::create_directories(device);
  std::ofstream(device / "latency_timer") << timer << "\n";
  return (dir.path / "sys").string();
}

cli_test::CliResult detect(const std::string& sysfs, const std::string& arguments) {
  return cli_test::run_shell("RANGEKIT_SYSFS_ROOT='" + sysfs + "' " + rangekit::test::cli_path() + " detect " +
                             arguments + " 2>&1 </dev/null");
}

TEST(DetectLatency, AFactoryFtdiTimerIsSaidWithWhatItCostsAPollAndTheUdevRule) {
  TempDir dir;
  auto quiet = rangekit::PseudoTerminal::open((dir.path / "adapter").string());
  ASSERT_TRUE(quiet.ok()) << quiet.error().describe();
  const std::string port = (*quiet)->public_path();
  const auto tty = std::filesystem::canonical(port).filename().string();
  const auto run = detect(fake_sysfs(dir, port, "16"), "--port " + port + " --baud 115200 --timeout 50");
  EXPECT_EQ(run.exit_code, 5) << run.output;  // nobody answers on the pty
  EXPECT_TRUE(contains(run.output, tty + ": its USB serial adapter holds each short reply until its 16 ms latency"))
      << run.output;
  EXPECT_TRUE(contains(run.output, "at most 62 polls a second")) << run.output;
  EXPECT_TRUE(contains(run.output, "echo 1 > /sys/bus/usb-serial/devices/" + tty + "/latency_timer")) << run.output;
  EXPECT_TRUE(contains(run.output, "/lib/udev/rules.d/99-rangekit-ftdi-latency.rules")) << run.output;
  // The rule it names is the one the package ships, and it sets the timer it talks about.
  const std::string rule = ls5_driver_test::read_file(std::string(rangekit::test::source_dir()) +
                                                      "/packaging/udev/99-rangekit-ftdi-latency.rules");
  EXPECT_TRUE(contains(rule,
                       "#ACTION==\"add\", SUBSYSTEM==\"usb-serial\", DRIVER==\"ftdi_sio\", "
                       "ATTR{latency_timer}=\"1\""))
      << rule;
}

TEST(DetectLatency, OneMillisecondIsSaidWithoutAdviceAndAPortWithoutATimerSaysNothing) {
  TempDir dir;
  auto quiet = rangekit::PseudoTerminal::open((dir.path / "adapter").string());
  ASSERT_TRUE(quiet.ok()) << quiet.error().describe();
  const std::string port = (*quiet)->public_path();
  const auto tty = std::filesystem::canonical(port).filename().string();
  auto run = detect(fake_sysfs(dir, port, "1"), "--port " + port + " --baud 115200 --timeout 50");
  EXPECT_TRUE(contains(run.output, tty + ": USB serial latency timer 1 ms")) << run.output;
  EXPECT_FALSE(contains(run.output, "udev")) << run.output;

  const TempDir empty;
  run = detect(empty.path.string(), "--port " + port + " --baud 115200 --timeout 50");
  EXPECT_FALSE(contains(run.output, "latency")) << run.output;
}

// With --json the findings stay one JSON object a line, each with the port's timer.
TEST(DetectLatency, EachJsonFindingCarriesItsPortsTimer) {
  TempDir dir;
  const auto port = (dir.path / "ls5").string();
  Child ls5({"sim", "ls5", "--port", port});
  ASSERT_TRUE(contains(ls5.read_line(), "ready:"));
  const auto sysfs = fake_sysfs(dir, port, "16");
  const auto found = cli_test::run_shell("RANGEKIT_SYSFS_ROOT='" + sysfs + "' " + rangekit::test::cli_path() +
                                         " detect --port " + port + " --baud 115200 --json 2>/dev/null </dev/null");
  EXPECT_EQ(found.exit_code, 0) << found.output;
  ASSERT_TRUE(contains(found.output, R"("family":"ls5")")) << found.output;
  EXPECT_TRUE(contains(found.output, R"("latency_timer_ms":16)")) << found.output;
  EXPECT_FALSE(contains(found.output, "polls a second")) << "the advice goes to stderr: " << found.output;
}

}  // namespace
