// The opt-in hardware tier (tests/hardware) is itself tested here: with no device
// in the environment every test skips; pointed at the emulators' ptys and UDP
// stream (as a user points it at /dev/ttyUSB0) every test runs and passes; pointed
// at a port that is not there it fails and names the port.
#include <gtest/gtest.h>
#include "build_paths.hpp"
#include "cli/cli_run.hpp"

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "ls5_driver/cli_process.hpp"
#include "rangekit/core/udp.hpp"

namespace {

using ls5_driver_test::Child;

using cli_test::contains;

struct TierRun {
  int exit_code = -1;
  std::string output;
};

TierRun run_tier(const std::string& environment) {
  const auto binary = std::filesystem::path(rangekit::test::cli_path()).parent_path() / "rangekit_hardware_tests";
  // `env -u` first: a developer's own RANGEKIT_* settings must not leak into this test.
  const std::string command =
      "env -u RANGEKIT_ULS_PORT -u RANGEKIT_LS5_PORT -u RANGEKIT_LS5_UDP -u RANGEKIT_HW_WRITE " + environment + " " +
      binary.string() + " 2>&1";
  TierRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[4096];
  std::size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) run.output.append(buffer, got);
  const int status = ::pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

class HardwareTier : public ::testing::Test {
 protected:
  ls5_driver_test::TempDir temp_;
  const std::filesystem::path& dir_ = temp_.path;
};

TEST_F(HardwareTier, SkipsEveryTestWithoutADevice) {
  const TierRun run = run_tier("");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(contains(run.output, "[  SKIPPED ] 11 tests")) << run.output;
  EXPECT_TRUE(contains(run.output, "set RANGEKIT_ULS_PORT to run against a sensor")) << run.output;
}

TEST_F(HardwareTier, RunsEveryTestAgainstTheEmulators) {
  std::uint16_t udp_port = 0;
  {
    auto probe = rangekit::UdpSocket::bind(rangekit::Endpoint{"127.0.0.1", 0});
    ASSERT_TRUE(probe);
    udp_port = probe->local_endpoint().port;
  }
  const std::string udp = "127.0.0.1:" + std::to_string(udp_port);
  const auto uls_port = (dir_ / "uls-config").string();
  const auto ls5_port = (dir_ / "ls5").string();
  Child uls({"sim", "uls", "--config-port", uls_port});
  ASSERT_TRUE(contains(uls.read_line(), "ready:"));
  Child ls5({"sim", "ls5", "--port", ls5_port, "--udp", udp});
  ASSERT_TRUE(contains(ls5.read_line(), "ready:"));

  const TierRun run = run_tier("RANGEKIT_ULS_PORT=" + uls_port + " RANGEKIT_LS5_PORT=" + ls5_port +
                               " RANGEKIT_LS5_UDP=" + udp + " RANGEKIT_HW_WRITE=1");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(contains(run.output, "[  PASSED  ] 11 tests")) << run.output;
  EXPECT_FALSE(contains(run.output, "SKIPPED")) << run.output;
  EXPECT_TRUE(contains(run.output, "LS5 at address 1: range 40.001 mm, serial 157")) << run.output;
}

TEST_F(HardwareTier, FailsAndNamesAPortThatIsNotThere) {
  const auto missing = (dir_ / "ttyUSB9").string();
  const TierRun run = run_tier("RANGEKIT_ULS_PORT=" + missing);
  EXPECT_NE(run.exit_code, 0) << run.output;
  EXPECT_TRUE(contains(run.output, "cannot open " + missing)) << run.output;
  EXPECT_TRUE(contains(run.output, "[  FAILED  ] UlsHardware.IdentifiesTheUnit")) << run.output;
}

}  // namespace
