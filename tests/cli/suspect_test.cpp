// Suspect samples against the emulators (U102, L71): a target jumping further than
// max_speed allows is marked suspect with the reason; `--drop-suspect` leaves it out. The
// scenes jump every second (a 1 ms leg), so any run of a few seconds meets several jumps.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli/cli_run.hpp"
#include "ls5_driver/cli_process.hpp"

namespace {

using ls5_driver_test::Child;
using ls5_driver_test::run_cli;
using ls5_driver_test::TempDir;

using cli_test::contains;

struct Counts {
  int samples = 0;
  int suspect = 0;
  int jump_reasons = 0;
};

Counts count_samples(const std::string& jsonl) {
  Counts counts;
  std::istringstream lines(jsonl);
  std::string line;
  while (std::getline(lines, line)) {
    const auto item = nlohmann::json::parse(line, nullptr, false);
    if (!item.is_object() || !item.contains("kind")) continue;
    ++counts.samples;
    if (item.value("suspect", false)) {
      ++counts.suspect;
      if (item.value("suspect_reason", std::string()).rfind("jump: ", 0) == 0) ++counts.jump_reasons;
    }
  }
  return counts;
}

void write_text(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

// LS5 100/200 (range 200 mm): 120 mm for a second, then 280 mm for a second, and back; the
// default max_speed is the range a second (0.2 m/s), so a 160 mm step in 10 ms is impossible.
constexpr const char* ls5_jumping_scene = R"toml(
[target]
path = [[0.0, 120.0], [1.0, 120.0], [1.001, 280.0], [2.0, 280.0], [2.001, 120.0]]
repeat = true
)toml";

// ULS: 20 m for a second, then 40 m: far beyond the default 25 m/s at 100 lines a second.
constexpr const char* uls_jumping_scene = R"toml(
[[targets]]
path = [[0.0, 20.0], [1.0, 20.0], [1.001, 40.0], [2.0, 40.0], [2.001, 20.0]]
repeat = true
)toml";

// L71: formula 8.1 and the ±0.15 % of table 3.1 judge each record; a jump is flagged, and the
// sensor's own noise (clamped to ±0.15 % in the emulator) never is.
TEST(SuspectCli, L71_Ls5JumpsAreMarkedAndDropSuspectLeavesThemOut) {
  const TempDir temp;
  write_text(temp.path / "scene.toml", ls5_jumping_scene);
  const std::string port = (temp.path / "ls5").string();
  Child sim({"sim", "ls5", "--port", port, "--model", "100/200", "--scene", (temp.path / "scene.toml").string()});
  ASSERT_TRUE(contains(sim.read_line(), "ready:"));

  auto marked = run_cli(temp.path, {"ls5", "stream", "--port", port, "--count", "350", "--format", "jsonl"});
  ASSERT_EQ(marked.exit_code, 0) << marked.err;
  const Counts all = count_samples(marked.out);
  EXPECT_EQ(all.samples, 350);
  EXPECT_GE(all.suspect, 1) << "350 records at 10 ms meet at least two jumps";
  EXPECT_EQ(all.jump_reasons, all.suspect);
  // A jump is flagged until the median of five has moved: at most three records a jump, and
  // at most four jumps in 3.5 s (plus a slow start under a sanitizer).
  EXPECT_LE(all.suspect, 3 * 8);

  auto dropped =
      run_cli(temp.path, {"ls5", "stream", "--port", port, "--count", "350", "--format", "jsonl", "--drop-suspect"});
  ASSERT_EQ(dropped.exit_code, 0) << dropped.err;
  const Counts kept = count_samples(dropped.out);
  EXPECT_EQ(kept.samples, 350) << "--count counts the samples written";
  EXPECT_EQ(kept.suspect, 0);
  EXPECT_FALSE(contains(dropped.out, "suspect"));
}

// U102: §9 "±4 cm typical" plus max_speed: the ULS's 20 m step in 10 ms is flagged; with
// --max-speed 1e5 (1000 m in 10 ms) it is possible and nothing is; --drop-suspect leaves the
// flagged lines out.
TEST(SuspectCli, U102_UlsJumpsAreMarkedAndDropSuspectLeavesThemOut) {
  const TempDir temp;
  write_text(temp.path / "scene.toml", uls_jumping_scene);
  const std::string port = (temp.path / "uls-config").string();
  Child sim({"sim", "uls", "--config-port", port, "--port", (temp.path / "uls").string(), "--scene",
             (temp.path / "scene.toml").string()});
  ASSERT_TRUE(contains(sim.read_line(), "ready:"));
  // 100 lines a second: PRF 2000 Hz / 20 pulses per measurement (§9 "PRF/PPM").
  auto set = run_cli(temp.path, {"uls", "set", "--port", port, "averaging-weight=16", "ppm=20", "prf-hz=2000"});
  ASSERT_EQ(set.exit_code, 0) << set.err;

  auto marked = run_cli(temp.path, {"uls", "stream", "--port", port, "--count", "350", "--format", "jsonl"});
  ASSERT_EQ(marked.exit_code, 0) << marked.err;
  const Counts all = count_samples(marked.out);
  EXPECT_EQ(all.samples, 350);
  EXPECT_GE(all.suspect, 1);
  EXPECT_EQ(all.jump_reasons, all.suspect);

  auto lenient = run_cli(
      temp.path, {"uls", "stream", "--port", port, "--count", "350", "--format", "jsonl", "--max-speed", "1e5"});
  ASSERT_EQ(lenient.exit_code, 0) << lenient.err;
  EXPECT_EQ(count_samples(lenient.out).suspect, 0);

  auto dropped =
      run_cli(temp.path, {"uls", "stream", "--port", port, "--count", "350", "--format", "jsonl", "--drop-suspect"});
  ASSERT_EQ(dropped.exit_code, 0) << dropped.err;
  EXPECT_EQ(count_samples(dropped.out).samples, 350);
  EXPECT_FALSE(contains(dropped.out, "suspect"));
}

}  // namespace
