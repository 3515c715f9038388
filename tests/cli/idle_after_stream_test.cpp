// U86: what `stream` and `capture` leave behind, read from the emulators' control sockets.
// A unit the host started is idle again when the command ends; a ULS found measuring keeps
// measuring. (`demo`: cli_test.cpp, LiveDemoStreamsBothSensorsAndCapturesThem.)
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli/cli_run.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/sim/control_socket.hpp"

namespace {

using ls5_driver_test::Child;
using ls5_driver_test::run_cli;

using cli_test::contains;

// One `outputs` field of the only device behind a control socket.
nlohmann::json output(const std::string& control, const char* field) {
  auto client = rangekit::ControlClient::connect(control);
  if (!client) return {};
  auto reply = client->request({{"cmd", "outputs"}});
  if (!reply) return {};
  const nlohmann::json& device = reply->contains("devices") ? (*reply)["devices"][0] : *reply;
  return device.value(field, nlohmann::json{});
}

struct Emulators {
  std::string uls_port;
  std::string uls_control;
  std::string ls5_port;
  std::string ls5_control;
  Child uls;
  Child ls5;
  explicit Emulators(const std::filesystem::path& dir)
      : uls_port((dir / "uls-config").string()),
        uls_control((dir / "uls.control").string()),
        ls5_port((dir / "ls5").string()),
        ls5_control((dir / "ls5.control").string()),
        uls({"sim", "uls", "--port", (dir / "uls").string(), "--config-port", uls_port, "--control", uls_control}),
        ls5({"sim", "ls5", "--port", ls5_port, "--control", ls5_control}) {}
  bool ready() { return contains(uls.read_line(), "ready:") && contains(ls5.read_line(), "ready:"); }
};

// §8 Measurement Stop ("$ST") ends what Start Measurement began; LS5 table 9.1 "SB: Stop the
// stream". After `uls stream` / `ls5 stream` of an idle unit, neither is left running.
TEST(IdleAfterStream, U86_StreamLeavesBothFamiliesIdle) {
  const ls5_driver_test::TempDir temp;
  Emulators sim(temp.path);
  ASSERT_TRUE(sim.ready());
  ASSERT_EQ(output(sim.uls_control, "measuring"), false);

  auto run = run_cli(temp.path, {"uls", "stream", "--port", sim.uls_port, "--count", "3", "--format", "jsonl"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(output(sim.uls_control, "measuring"), false);

  run = run_cli(temp.path, {"ls5", "stream", "--port", sim.ls5_port, "--count", "3", "--format", "jsonl"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(output(sim.ls5_control, "streaming"), false);
}

// §2 ULS Autostart: a unit may be measuring before the host comes (and feed a PLC through its
// 4-20 mA loop or trip line). `uls stream` neither restarts (GO) nor stops (ST) it.
TEST(IdleAfterStream, U86_AUlsFoundMeasuringKeepsMeasuring) {
  const ls5_driver_test::TempDir temp;
  Emulators sim(temp.path);
  ASSERT_TRUE(sim.ready());
  ASSERT_EQ(run_cli(temp.path, {"uls", "start", "--port", sim.uls_port}).exit_code, 0);
  ASSERT_EQ(output(sim.uls_control, "measuring"), true);
  const auto run = run_cli(temp.path, {"uls", "stream", "--port", sim.uls_port, "--count", "3", "--format", "jsonl"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_FALSE(contains(run.err, "bad_frame")) << run.err;  // U85
  EXPECT_EQ(output(sim.uls_control, "measuring"), true);
}

// U86: after `rangekit capture --duration 2` a unit the host started is no longer measuring.
TEST(IdleAfterStream, U86_CaptureLeavesBothFamiliesIdle) {
  const ls5_driver_test::TempDir temp;
  Emulators sim(temp.path);
  ASSERT_TRUE(sim.ready());
  const auto file = (temp.path / "both.sqlite").string();
  const auto run = run_cli(temp.path, {"capture", "--out", file, "--uls", sim.uls_port, "--ls5", sim.ls5_port,
                                       "--ls5-thinning", "10", "--duration", "2"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(output(sim.uls_control, "measuring"), false);
  EXPECT_EQ(output(sim.ls5_control, "streaming"), false);
}

}  // namespace
