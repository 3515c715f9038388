// End-to-end: `rangekit replay` on captures written by the library.
#include <gtest/gtest.h>

#include "rangekit/ls5/family.hpp"
#include "rangekit/record/capture.hpp"
#include "record/cli_process.hpp"
#include "record/fake_source.hpp"
#include "record/temp_dir.hpp"

namespace rangekit::record {
namespace {

using namespace testing;

std::size_t count_of(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + part.size())) ++count;
  return count;
}

std::string make_capture(const TempDir& dir, const std::vector<StreamItem>& items) {
  const auto path = dir.file("capture.sqlite");
  auto capture = open_capture(path);
  EXPECT_TRUE(capture.ok());
  if (!capture.ok()) return path;
  for (const auto& item : items) {
    if (const auto* sample = std::get_if<Sample>(&item)) {
      EXPECT_TRUE((*capture)->write(*sample).ok());
    } else {
      EXPECT_TRUE((*capture)->write_event(std::get<StreamEvent>(item)).ok());
    }
  }
  return path;
}

struct Finished {
  int exit_code;
  std::string out;
  std::string err;
};

Finished run(const std::vector<std::string>& arguments) {
  CliProcess process(arguments);
  const int code = process.finish();
  return {code, process.out(), process.err()};
}

TEST(ReplayCli, JsonlAtFullSpeedWithEventsOnStderr) {
  TempDir dir;
  const auto capture = make_capture(dir, {uls_error(), event(StreamEventKind::disconnected, "gone"),
                                          ls5_result(12345, 1234.5, ls5::SignalState::ok)});
  const auto result = run({"replay", capture, "--format", "jsonl", "--full-speed"});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out,
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"uls\",\"address\":3,\"source\":\"/dev/ttyUSB0\","
            "\"kind\":\"error\",\"error\":4,\"error_text\":\"Lock Not Found (display: Target Not Found)\"}\n"
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"event\":\"disconnected\",\"message\":\"gone\",\"count\":0}\n"
            "{\"time\":\"2026-11-26T01:02:03.456Z\",\"device\":\"ls5\",\"address\":null,"
            "\"source\":\"udp:127.0.0.1:5000\",\"kind\":\"result\",\"code\":12345,\"distance_mm\":1234.50,"
            "\"signal\":\"ok\"}\n");
  // Not a terminal: no status line, only the event.
  EXPECT_EQ(result.err, "rangekit replay: 01:02:03.456 disconnected: gone\n");
}

TEST(ReplayCli, CsvCountAndDeviceFilter) {
  TempDir dir;
  const auto capture = make_capture(
      dir, {uls_error(), ls5_result(12345, 1234.5, ls5::SignalState::ok), ls5_result(1, 2.0, ls5::SignalState::ok)});
  const auto result = run({"replay", capture, "--format", "csv", "--full-speed", "--count", "1", "--device", "ls5"});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out,
            "time,device,address,source,kind,distance_m,pulse_width_ns,targets,presence,pulses_between_events,pulses_"
            "overflow,error,"
            "code,distance_mm,signal,derivative_mm,error_text,suspect,suspect_reason\n"
            "2026-11-26T01:02:03.456Z,ls5,,udp:127.0.0.1:5000,result,,,,,,,,12345,1234.50,ok,,,false,\n");
}

// U102/L71: a replay shows the flags as recorded (it does not judge again)
// and --drop-suspect leaves the suspect samples out.
TEST(ReplayCli, U102_L71_ReplayKeepsTheRecordedFlagsAndDropSuspectLeavesThemOut) {
  TempDir dir;
  auto corrupt = ls5_result(34845, 139.38, ls5::SignalState::ok);
  corrupt.suspect = true;
  corrupt.suspect_reason = "jump";
  const auto capture = make_capture(dir, {ls5_result(24845, 99.38, ls5::SignalState::ok), corrupt});
  const auto all = run({"replay", capture, "--format", "jsonl", "--full-speed"});
  EXPECT_EQ(all.exit_code, 0) << all.err;
  EXPECT_EQ(count_of(all.out, "\"kind\""), 2u);
  EXPECT_EQ(count_of(all.out, "\"suspect\":true,\"suspect_reason\":\"jump\""), 1u);
  const auto kept = run({"replay", capture, "--format", "jsonl", "--full-speed", "--drop-suspect"});
  EXPECT_EQ(kept.exit_code, 0) << kept.err;
  EXPECT_EQ(count_of(kept.out, "\"kind\""), 1u);
  EXPECT_EQ(count_of(kept.out, "\"code\":24845"), 1u);
  EXPECT_EQ(count_of(kept.out, "suspect"), 0u);
}

TEST(ReplayCli, TextToAFile) {
  TempDir dir;
  auto bus_unit = uls_averaging();
  bus_unit.address = 'A';  // the capture keeps the byte (65); a person reads the character
  const auto capture = make_capture(dir, {bus_unit});
  const auto out = dir.file("out.txt");
  const auto result = run({"replay", capture, "--full-speed", "--out", out});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out, "");
  EXPECT_EQ(read_file(out), "01:02:03.456 uls A  12.345 m  pw 18.000 ns\n");
}

TEST(ReplayCli, NotACaptureIsExitFourNamingTheFile) {
  TempDir dir;
  const auto path = dir.file("notes.txt");
  write_file(path, std::string(3000, 'n'));
  const auto result = run({"replay", path});
  EXPECT_EQ(result.exit_code, 4);  // docs/cli.md: cannot open or read a file
  EXPECT_NE(result.err.find(path), std::string::npos) << result.err;
  EXPECT_EQ(read_file(path), std::string(3000, 'n'));
}

TEST(ReplayCli, DiskFullIsExitSeven) {
  TempDir dir;
  const auto capture = make_capture(dir, {uls_averaging()});
  const auto result = run({"replay", capture, "--full-speed", "--out", "/dev/full"});
  EXPECT_EQ(result.exit_code, 7);  // docs/cli.md: output could not be written
  EXPECT_NE(result.err.find("/dev/full"), std::string::npos) << result.err;
}

TEST(ReplayCli, FullSpeedAndSpeedTogetherIsAUsageError) {
  TempDir dir;
  const auto capture = make_capture(dir, {uls_averaging()});
  EXPECT_EQ(run({"replay", capture, "--full-speed", "--speed", "2"}).exit_code, 2);
  EXPECT_EQ(run({"replay", capture, "--full-speed", "--pace"}).exit_code, 2);
  EXPECT_EQ(run({"replay", capture, "--pace", "--speed", "2"}).exit_code, 2);
  EXPECT_EQ(run({"replay", capture, "--format", "xml"}).exit_code, 2);
}

// Into a pipe or a file, a replay is an export: it does not wait the recording's length
// (an hour here) unless --pace or --speed asks for it.
TEST(ReplayCli, IntoAPipeOrAFileItRunsAtFullSpeed) {
  TempDir dir;
  const auto capture = make_capture(dir, {uls_averaging(0ms), uls_averaging(3600s)});
  const auto piped = run({"replay", capture, "--format", "jsonl"});
  EXPECT_EQ(piped.exit_code, 0) << piped.err;
  EXPECT_EQ(count_of(piped.out, "\"pulse_width_ns\":18.000}\n"), 2u) << piped.out;
  const auto out = dir.file("export.csv");
  const auto exported = run({"replay", capture, "--format", "csv", "--out", out});
  EXPECT_EQ(exported.exit_code, 0) << exported.err;
  EXPECT_EQ(count_of(read_file(out), ",averaging,"), 2u) << read_file(out);
}

TEST(ReplayCli, SigintClosesCleanlyWithExit130) {
  TempDir dir;
  const auto capture = make_capture(dir, {uls_averaging(0ms), uls_averaging(3600s)});  // an hour apart
  const auto copy = dir.file("copy.sqlite");
  // --pace: into a pipe, replay would otherwise not wait the hour.
  CliProcess process({"replay", capture, "--format", "jsonl", "--pace", "--capture", copy});
  ASSERT_TRUE(process.wait_for_stdout("\"pulse_width_ns\":18.000}\n", 10s)) << process.err();
  process.signal(SIGINT);
  EXPECT_EQ(process.finish(), 130);
  EXPECT_NE(process.err().find("interrupted after 1 samples"), std::string::npos) << process.err();
  // The capture written on the way was closed cleanly and holds the sample.
  auto replay_copy = CliProcess({"replay", copy, "--format", "csv", "--full-speed"});
  EXPECT_EQ(replay_copy.finish(), 0);
  EXPECT_EQ(replay_copy.out(),
            "time,device,address,source,kind,distance_m,pulse_width_ns,targets,presence,pulses_between_events,pulses_"
            "overflow,error,"
            "code,distance_mm,signal,derivative_mm,error_text,suspect,suspect_reason\n"
            "2026-11-26T01:02:03.456Z,uls,3,/dev/ttyUSB0,averaging,12.3450,18.000,,,,,,,,,,,false,\n");
}

}  // namespace
}  // namespace rangekit::record
