// End-to-end checks of the rangekit binary: exit codes and decoded output.
#include <gtest/gtest.h>
#include "build_paths.hpp"

#include <unistd.h>
#include <filesystem>
#include <string>

#include "cli/cli_run.hpp"

namespace {

using cli_test::run_cli;

TEST(Cli, DemoWalkthroughDecodesBothFamilies) {
  const auto run = run_cli("demo --walkthrough");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("unit 'Z' (0x5A): set Measurement Mode = 1 (averaging)"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("version LS5.6.0, lower boundary 8.1234 mm, range 40.001 mm, serial 157"),
            std::string::npos);
  EXPECT_NE(run.output.find("checksum"), std::string::npos);
}

// The main job: both emulators streamed live through the drivers and captured
// into one SQLite file, which replays.
TEST(Cli, LiveDemoStreamsBothSensorsAndCapturesThem) {
  const auto capture =
      std::filesystem::temp_directory_path() / ("rangekit-demo-test-" + std::to_string(::getpid()) + ".sqlite");
  const auto run = run_cli("demo --seconds 4 --format jsonl --capture " + capture.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("\"device\":\"uls\""), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("\"device\":\"ls5\""), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("\"distance_m\""), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("\"distance_mm\""), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("replay " + capture.string()), std::string::npos) << run.output;
  // U86: the demo's streams started both sensors and stop both (ULS ST, LS5 SB).
  EXPECT_NE(run.output.find("Left as found: ULS not measuring, LS5 not streaming"), std::string::npos) << run.output;

  const auto replay = run_cli("replay " + capture.string() + " --full-speed --format jsonl");
  EXPECT_EQ(replay.exit_code, 0) << replay.output;
  EXPECT_NE(replay.output.find("\"device\":\"uls\""), std::string::npos) << replay.output;
  EXPECT_NE(replay.output.find("\"device\":\"ls5\""), std::string::npos) << replay.output;
  // The count the demo prints is what the file holds: one replayed line per sample.
  const auto said = run.output.find("Captured ");
  ASSERT_NE(said, std::string::npos) << run.output;
  const auto captured = std::stoull(run.output.substr(said + 9));
  std::size_t replayed = 0;
  for (auto at = replay.output.find("\"device\":"); at != std::string::npos;
       at = replay.output.find("\"device\":", at + 1)) {
    ++replayed;
  }
  EXPECT_GT(captured, 0U);
  EXPECT_EQ(replayed, captured) << replay.output.substr(0, 400);
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(capture.string() + suffix);
}

// The replay command the demo prints works as printed from any folder: the binary and the
// capture by absolute path, although the capture was named relative to the demo's folder.
TEST(Cli, TheDemosReplayHintRunsFromAnyFolder) {
  const auto dir = std::filesystem::temp_directory_path() / ("rangekit-demo-hint-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto demo = cli_test::run_shell("cd " + dir.string() + " && " + rangekit::test::cli_path() +
                                        " demo --seconds 2 --format jsonl --capture hint.sqlite < /dev/null 2>&1");
  ASSERT_EQ(demo.exit_code, 0) << demo.output;
  const std::string label = "Replay it:  ";
  const auto at = demo.output.find(label);
  ASSERT_NE(at, std::string::npos) << demo.output;
  const auto end = demo.output.find('\n', at);
  const std::string hint = demo.output.substr(at + label.size(), end - at - label.size());
  EXPECT_NE(hint.find((dir / "hint.sqlite").string()), std::string::npos) << hint;
  const auto replay = cli_test::run_shell("cd / && " + hint + " < /dev/null 2>&1");
  EXPECT_EQ(replay.exit_code, 0) << hint << "\n" << replay.output;
  EXPECT_NE(replay.output.find("\"device\":\"uls\""), std::string::npos) << replay.output;
  std::filesystem::remove_all(dir);
}

TEST(Cli, VersionComesFromTheBuild) {
  const auto run = run_cli("--version");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find(std::string("rangekit ") + rangekit::test::project_version()), std::string::npos)
      << run.output;
}

TEST(Cli, DecodeUlsBinningLines) {
  // §9 binning output lines, U10: range in metres, strength = hits.
  const auto run = run_cli("decode uls --mode binning", "$BM,0,2,4.572,42\r$BM,1,2,1234.567,7\r");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("binning target 1 of 2: 4.572 m, strength 42"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("binning target 2 of 2: 1234.567 m, strength 7"), std::string::npos) << run.output;
}

TEST(Cli, DecodeUlsTakesTheDisplaySettingsOwnValueNames) {
  // §8 DM 2 "range and intensity", §9 "$BM,xxxx.xxx,yyyyyyy": the width in ps (U8), shown in ns.
  // The names are the ones `uls get` prints for `display` and `mode`.
  const auto both = run_cli("decode uls --display range-and-intensity", "$BM,50.000,33238\r");
  EXPECT_EQ(both.exit_code, 0) << both.output;
  EXPECT_NE(both.output.find("averaging: 50.000 m pulse width 33.238 ns"), std::string::npos) << both.output;
  const auto intensity = run_cli("decode uls --display intensity", "$BM,33238\r");
  EXPECT_EQ(intensity.exit_code, 0) << intensity.output;
  EXPECT_NE(intensity.output.find("averaging: pulse width 33.238 ns"), std::string::npos) << intensity.output;
  const auto look_down = run_cli("decode uls --mode look-down", "$BM,1\r");
  EXPECT_EQ(look_down.exit_code, 0) << look_down.output;
  EXPECT_NE(look_down.output.find("look down: ON (presence)"), std::string::npos) << look_down.output;
  // The dashboard's word for DM 2 is not a value of the setting.
  const auto refused = run_cli("decode uls --display both", "$BM,50.000,33238\r");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("range-and-intensity"), std::string::npos) << refused.output;
}

// §9 "xxxx.xx = range (feet)": a unit in feet (MU 0), named as `uls get` names `units`;
// 40.50 ft is 12.3444 m (0.3048 m to the foot).
TEST(Cli, DecodeUlsTakesTheUnitsSettingsOwnValueNames) {
  const auto feet = run_cli("decode uls --units feet", "$BM,40.50\r");
  EXPECT_EQ(feet.exit_code, 0) << feet.output;
  EXPECT_NE(feet.output.find("averaging: 12.344 m"), std::string::npos) << feet.output;
  const auto refused = run_cli("decode uls --units ft", "$BM,40.50\r");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("feet"), std::string::npos) << refused.output;
}

// The settings a unit reads back (§8 MU 0 feet, DM 2 range and intensity) change how its next
// BM lines read, without options: what a tap needs, which sees the host read them.
TEST(Cli, DecodeUlsReadsMeasurementsAsTheSettingsReadBackSay) {
  const auto run = run_cli("decode uls", "$BM,50.000\r$MU,0\r$DM,2\r$BM,164.04,33238\r");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("averaging: 50.000 m"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("averaging: 49.999 m pulse width 33.238 ns"), std::string::npos) << run.output;
}

TEST(Cli, DecodeLs5RequestsFromTheHost) {
  const auto run = run_cli("decode ls5 --from host", "#01ON\r#02W0B01\r");  // §9.4
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("sensor 02: Write the parameter: parameter 0B (Data pre-filtering type) = 01"),
            std::string::npos)
      << run.output;
}

TEST(Cli, DecodeReportsGarbageWithExitCode3) {
  const auto run = run_cli("decode ls5", std::string("xx!25000\r!5000", 14));
  EXPECT_EQ(run.exit_code, 3) << run.output;
  EXPECT_NE(run.output.find("rejected: bytes before the start of a frame"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("without a terminating CR"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("code 25000"), std::string::npos) << run.output;
}

TEST(Cli, MissingFileIsExitCode4) {
  const auto run = run_cli("decode uls /nonexistent/rangekit-capture.bin");
  EXPECT_EQ(run.exit_code, 4) << run.output;
  EXPECT_NE(run.output.find("cannot open /nonexistent/rangekit-capture.bin"), std::string::npos);
}

TEST(Cli, TablesComeFromTheRegistries) {
  const auto run = run_cli("tables uls-commands");
  EXPECT_EQ(run.exit_code, 0);
  // 36 commands of §8 plus the header line.
  EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 37) << run.output;
  const auto parameters = run_cli("tables ls5-parameters --markdown");
  EXPECT_NE(parameters.output.find("| 0D | Number of points of the median filter"), std::string::npos)
      << parameters.output;
}

TEST(Cli, UnknownSubcommandIsAUsageError) {
  EXPECT_EQ(run_cli("frobnicate").exit_code, 2);
  EXPECT_EQ(run_cli("decode").exit_code, 2);  // family missing
  EXPECT_EQ(run_cli("decode uls --mode sideways").exit_code, 2);
  EXPECT_EQ(run_cli("--help").exit_code, 0);
}

}  // namespace
