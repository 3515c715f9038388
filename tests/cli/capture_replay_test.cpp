// `rangekit sim replay` of a `rangekit capture` file: the family's emulator follows the
// captured readings, so a host streaming from the replay hears the captured distance, not
// the emulator's own; `tap compare` says a capture has no requests to compare.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

#include "ls5_driver/cli_process.hpp"

namespace {

using ls5_driver_test::Child;
using ls5_driver_test::TempDir;

struct CapturedTarget {
  std::string family;
  std::string scene;     // the first emulator's: a target where the emulator never puts one itself
  std::string channel;   // the reading's channel in the stream's JSON lines
  double reading = 0;    // what the capture holds ...
  double tolerance = 0;  // ... give or take the emulator's own noise
};
void PrintTo(const CapturedTarget& target, std::ostream* out) { *out << target.family; }

class CaptureReplay : public ::testing::TestWithParam<CapturedTarget> {};

TEST_P(CaptureReplay, StreamsTheCapturedReadingsThroughTheFamilysEmulator) {
  const CapturedTarget& target = GetParam();
  TempDir dir;
  const std::string scene = (dir.path / "scene.toml").string();
  std::ofstream(scene) << target.scene;
  const std::string capture = (dir.path / "capture.sqlite").string();
  {
    const std::string port = (dir.path / "sensor").string();
    Child sim({"sim", target.family, "--port", port, "--scene", scene});
    ASSERT_NE(sim.read_line().find("ready"), std::string::npos);
    const auto captured = ls5_driver_test::run_cli(
        dir.path, {"capture", "--" + target.family, port, "--out", capture, "--count", "5", "--quiet"});
    ASSERT_EQ(captured.exit_code, 0) << captured.err;
  }
  const std::string port = (dir.path / "replayed").string();
  Child replay({"sim", "replay", capture, "--port", port});
  const std::string ready = replay.read_line();
  ASSERT_NE(ready.find("rangekit sim replay ready: " + port), std::string::npos) << ready;
  EXPECT_NE(ready.find("5 readings of " + target.channel), std::string::npos) << ready;
  const auto streamed = ls5_driver_test::run_cli(
      dir.path, {target.family, "stream", "--port", port, "--count", "3", "--format", "jsonl"});
  ASSERT_EQ(streamed.exit_code, 0) << streamed.err;
  int readings = 0;
  std::istringstream lines(streamed.out);
  for (std::string line; std::getline(lines, line);) {
    const auto sample = nlohmann::json::parse(line, nullptr, false);
    ASSERT_TRUE(sample.is_object()) << line;
    if (!sample.contains(target.channel)) continue;
    ++readings;
    EXPECT_NEAR(sample[target.channel].get<double>(), target.reading, target.tolerance) << line;
  }
  EXPECT_EQ(readings, 3) << streamed.out;

  const auto compared = ls5_driver_test::run_cli(dir.path, {"tap", "compare", capture});
  EXPECT_EQ(compared.exit_code, 3);
  EXPECT_NE(compared.err.find("is a capture: it keeps the readings, not the host's requests"), std::string::npos)
      << compared.err;
}

// The LS5's distance counts from its lower boundary (8.1234 mm in the emulator): 25.6234 is 17.5.
INSTANTIATE_TEST_SUITE_P(BothFamilies, CaptureReplay,
                         ::testing::Values(CapturedTarget{"uls",
                                                          "dust = 0\n[[targets]]\nname = \"a\"\ndistance_m = 12.34\n",
                                                          "distance_m", 12.34, 0.01},
                                           CapturedTarget{"ls5", "[target]\nposition_mm = 25.6234\nnoise_mm = 0\n",
                                                          "distance_mm", 17.5, 0.002}),
                         [](const auto& test) { return test.param.family; });

}  // namespace
