// Behaviour of the ULS model beyond the basics (docs/emulator-uls.md): error 86,
// gates, the pointer, look-down re-referencing, the §3 binning restart rule,
// received pulse widths, the minimum pulse width and the §9 range+intensity limit.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "rangekit/uls/emulator/firmware.hpp"
#include "rangekit/uls/uls.hpp"
#include "uls_emulator/helpers.hpp"

namespace rangekit::uls::emulator {
namespace {

using namespace std::chrono_literals;
using testing::Unit;

FirmwareOptions scene_of(std::vector<SceneTarget> targets, double noise = 0.0, double dust = 0.0) {
  FirmwareOptions options;
  options.scene.targets = std::move(targets);
  options.scene.ambient_noise = noise;
  options.scene.dust = dust;
  options.seed = 7;
  return options;
}

SceneTarget target_at(double metres, double reflectivity = 0.9, bool cooperative = false) {
  return SceneTarget{"t" + std::to_string(metres), Motion::fixed(metres), reflectivity, cooperative};
}

// Latest averaging range on the universal port after `span`, or the error line.
std::string last_line(Unit& unit, Nanos span = 1s) {
  (void)unit.take(universal_port);
  unit.run(span);
  const auto lines = unit.lines(universal_port);
  return lines.empty() ? std::string() : lines.back();
}

double range_of(const std::string& line) {
  const MeasurementContext context{Mode::averaging, DisplayMode::range, Units::metres, false};
  auto m = decode_measurement(as_bytes(line), context);
  EXPECT_TRUE(m) << line;
  if (!m) return -1;
  const auto* reading = std::get_if<AveragingReading>(&m->reading);
  return reading && reading->range ? reading->range->metres : -1;
}

// Binning targets of the last complete measurement among `lines`.
std::vector<BinningTarget> last_binning(const std::vector<std::string>& lines) {
  const MeasurementContext context{Mode::binning, DisplayMode::range, Units::metres, false};
  std::vector<BinningTarget> current;
  std::vector<BinningTarget> complete;
  for (const auto& line : lines) {
    auto m = decode_measurement(as_bytes(line), context);
    EXPECT_TRUE(m) << line;
    if (!m || !std::holds_alternative<BinningTarget>(m->reading)) continue;
    const auto target = std::get<BinningTarget>(m->reading);
    if (target.index == 0) current.clear();
    current.push_back(target);
    if (current.size() == target.count) complete = current;
  }
  return complete;
}

// docs/conformance.md U43
TEST(UlsBehaviour, StopWhileNotMeasuringIsErrorEightySix) {
  FirmwareOptions options;
  options.address = 'Z';
  Unit unit(std::move(options));
  EXPECT_EQ(unit.ask("$ST"), "$ER,86");  // §10 86 Instrument Not Measuring
  EXPECT_EQ(unit.ask("#ZST"), "#ZER,86");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  EXPECT_EQ(unit.ask("$ST"), "$OK");
  EXPECT_EQ(unit.ask("$ST"), "$ER,86");
  unit.ask("#\xF5ST");  // a broadcast stop acts silently, even on an idle unit
  EXPECT_EQ(unit.ask("$US"), "$US,1");
}

// docs/conformance.md U44, U48 (two targets: the noise filter drops the far returns of missed near pulses)
// U132 (kept): gates cut exactly at the set distance, though §2 says the short gate "has
// deliberately been set to occur sooner then the set point"; the amount is not given.
TEST(UlsBehaviour, ShortAndLongGatesChooseTheAveragingTarget) {
  Unit unit(scene_of({target_at(5.0), target_at(20.0)}));
  EXPECT_EQ(unit.ask("$PF,5000"), "$OK");
  EXPECT_EQ(unit.ask("$DM,1"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  auto measure = [&](std::string_view setting) {
    EXPECT_EQ(unit.ask(setting), "$OK") << setting;
    EXPECT_EQ(unit.ask("$GO"), "$OK");
    const std::string line = last_line(unit);
    EXPECT_EQ(unit.ask("$ST"), "$OK");
    return line;
  };
  EXPECT_NEAR(range_of(measure("$SG,0")), 5.0, 0.04);    // first target (§2 "first target system")
  EXPECT_NEAR(range_of(measure("$SG,10")), 20.0, 0.04);  // inside the short gate: ignored
  EXPECT_EQ(unit.ask("$SG,0"), "$OK");
  EXPECT_NEAR(range_of(measure("$LG,15")), 5.0, 0.04);
  EXPECT_EQ(measure("$LG,3"), "$ER,4");  // both beyond the long gate: target not found
  EXPECT_EQ(unit.ask("$LG,0"), "$OK");
  // Gates use the actual distance; the offset only changes what is reported (§2 Offset).
  EXPECT_EQ(unit.ask("$OF,10"), "$OK");
  EXPECT_NEAR(range_of(measure("$SG,10")), 30.0, 0.04);
  EXPECT_EQ(unit.ask("$SG"), "$SG,10.000");
}

// docs/conformance.md U44
TEST(UlsBehaviour, GatesRemoveBinningTargets) {
  Unit unit(scene_of({target_at(5.0), target_at(20.0)}));
  EXPECT_EQ(unit.ask("$MM,2"), "$OK");
  EXPECT_EQ(unit.ask("$BS,3"), "$OK");  // 8 inches: 104 m
  EXPECT_EQ(unit.ask("$PF,1000"), "$OK");
  EXPECT_EQ(unit.ask("$PO,1024,100"), "$OK");
  EXPECT_EQ(unit.ask("$BH,50"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  auto targets = [&](std::string_view setting) {
    EXPECT_EQ(unit.ask(setting), "$OK") << setting;
    EXPECT_EQ(unit.ask("$GO"), "$OK");
    (void)unit.take(universal_port);
    unit.run(500ms);
    const auto found = last_binning(unit.lines(universal_port));
    EXPECT_EQ(unit.ask("$ST"), "$OK");
    std::vector<double> ranges;
    for (const auto& t : found) ranges.push_back(t.range.metres);
    return ranges;
  };
  auto both = targets("$SG,0");
  ASSERT_EQ(both.size(), 2U);
  EXPECT_NEAR(both[0], 5.0, 0.21);
  EXPECT_NEAR(both[1], 20.0, 0.21);
  auto near_only = targets("$LG,10");
  ASSERT_EQ(near_only.size(), 1U);
  EXPECT_NEAR(near_only[0], 5.0, 0.21);
  EXPECT_EQ(unit.ask("$LG,0"), "$OK");
  auto far_only = targets("$SG,10");
  ASSERT_EQ(far_only.size(), 1U);
  EXPECT_NEAR(far_only[0], 20.0, 0.21);
}

// docs/conformance.md U45
TEST(UlsBehaviour, PointerFollowsPtAndPaAndIsReadOnTheControlInterface) {
  const auto dir = std::filesystem::temp_directory_path() / ("rangekit-uls-pointer-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  FirmwareOptions options;
  options.state_dir = dir.string();
  Unit unit(std::move(options));
  auto outputs = [&] { return unit.firmware->control({{"cmd", "outputs"}}, unit.now); };
  EXPECT_EQ(outputs()["pointer"], false);
  EXPECT_EQ(outputs()["laser_firing"], false);
  EXPECT_EQ(unit.ask("$PT,1"), "$OK");
  EXPECT_EQ(outputs()["pointer"], true);
  EXPECT_EQ(outputs()["laser_firing"], false);  // the pointer is not the ranging laser
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  EXPECT_EQ(outputs()["laser_firing"], true);
  EXPECT_EQ(unit.ask("$PT,0"), "$OK");  // accepted while measuring (U24)
  EXPECT_EQ(outputs()["pointer"], false);
  EXPECT_EQ(unit.ask("$ST"), "$OK");
  EXPECT_EQ(outputs()["laser_firing"], false);
  // PA: the pointer at power-up, once saved (§8 Pointer Autostart).
  EXPECT_EQ(unit.ask("$PA,1"), "$OK");
  EXPECT_EQ(unit.ask("$PA"), "$PA,1");
  EXPECT_EQ(outputs()["pointer"], false);  // PA does not switch the pointer now
  unit.firmware->power_cycle(unit.now);
  EXPECT_EQ(outputs()["pointer"], false);  // not saved: factory PA 0
  EXPECT_EQ(unit.ask("$PA,1"), "$OK");
  EXPECT_EQ(unit.ask("$SU"), "$OK");
  unit.firmware->power_cycle(unit.now);
  EXPECT_EQ(outputs()["pointer"], true);
  EXPECT_EQ(unit.ask("$PT,0"), "$OK");
  EXPECT_EQ(outputs()["pointer"], false);
  std::filesystem::remove_all(dir);
}

// docs/conformance.md U46
TEST(UlsBehaviour, LookDownTakesALongerDistanceAsTheNewReference) {
  // §3: not tripped, a distance longer than the reference becomes the reference "over an
  // adjustment period of a few seconds" (2 s here).
  Unit unit(scene_of({target_at(8.0, 0.5)}));
  EXPECT_EQ(unit.ask("$MM,3"), "$OK");
  EXPECT_EQ(unit.ask("$PF,3000,3000,3000"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(500ms);
  ASSERT_TRUE(unit.firmware->move_target(0, 9.0, unit.now));  // the ground drops away (a lid opened)
  unit.run(1500ms);
  // 1.5 s later the old reference (8 m) still holds: 8.5 m is not above its trip point.
  Scene object{{target_at(9.0, 0.5), target_at(8.5, 0.5)}, 0, 0};
  unit.firmware->set_scene(object, unit.now);
  unit.run(300ms);
  EXPECT_TRUE(unit.lines(universal_port).empty());
  EXPECT_FALSE(unit.firmware->outputs(unit.now).trip);
  // Every distance seen since the move is longer than 8 m; once that has lasted 2 s the
  // longest of them, the ground at 9 m, is the reference.
  unit.firmware->set_scene(Scene{{target_at(9.0, 0.5)}, 0, 0}, unit.now);
  unit.run(2500ms);
  EXPECT_TRUE(unit.lines(universal_port).empty());  // re-referencing is silent
  unit.firmware->set_scene(object, unit.now);
  unit.run(300ms);
  EXPECT_EQ(unit.lines(universal_port), std::vector<std::string>{"$BM,1"});  // 8.5 < 9 - 0.2
  EXPECT_TRUE(unit.firmware->outputs(unit.now).trip);
}

// docs/conformance.md U46
TEST(UlsBehaviour, LookDownReReferencesAfterTheDefaultTimeout) {
  // TT factory 107AC0 = 1,080,000 pulses = 360 s at 3000 PRF (§3, U34).
  Unit unit(scene_of({target_at(8.0, 0.5)}));
  EXPECT_EQ(unit.ask("$MM,3"), "$OK");
  EXPECT_EQ(unit.ask("$PF,3000,3000,3000"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(200ms);
  unit.firmware->set_scene(Scene{{target_at(8.0, 0.5), target_at(6.0, 0.5)}, 0, 0}, unit.now);
  unit.run(100ms);
  const auto tripped = unit.lines_with_times(universal_port);
  ASSERT_EQ(tripped.size(), 1U);
  EXPECT_EQ(tripped[0].text, "$BM,1");
  // Run in large steps: the firmware fires every pulse in between.
  auto run_to = [&](Nanos until) {
    while (unit.now < until) {
      unit.now = std::min(until, unit.now + Nanos(10s));
      unit.firmware->advance(unit.now);
      unit.collect();
    }
  };
  run_to(tripped[0].done + 359s);
  EXPECT_TRUE(unit.lines(universal_port).empty());
  EXPECT_TRUE(unit.firmware->outputs(unit.now).trip);
  run_to(tripped[0].done + 361s);
  const auto released = unit.lines_with_times(universal_port);
  ASSERT_EQ(released.size(), 1U);
  EXPECT_EQ(released[0].text, "$BM,0");
  const double after_s = static_cast<double>((released[0].done - tripped[0].done).count()) / 1e9;
  EXPECT_NEAR(after_s, 360.0, 0.05);
  EXPECT_FALSE(unit.firmware->outputs(unit.now).trip);
}

FirmwareOptions crowded_scene(std::size_t near_targets, bool with_far) {
  // Strong targets 5 m apart from 10 m fill their bins within ~11 pulses; far gray ones
  // (hit probability 0.25-0.4) take ~30 pulses to reach BH 10.
  std::vector<SceneTarget> targets;
  for (std::size_t i = 0; i < near_targets; ++i) targets.push_back(target_at(10.0 + 5.0 * static_cast<double>(i)));
  if (with_far) {
    for (double d = 150.0; d < 195.0; d += 10.0) targets.push_back(target_at(d, 0.2));
  }
  return scene_of(std::move(targets));
}

void start_crowded_binning(Unit& unit) {
  EXPECT_EQ(unit.ask("$MM,2"), "$OK");
  EXPECT_EQ(unit.ask("$BS,4"), "$OK");  // 16 inches: 208 m
  EXPECT_EQ(unit.ask("$PF,1000"), "$OK");
  EXPECT_EQ(unit.ask("$PO,1024,1000"), "$OK");
  EXPECT_EQ(unit.ask("$BH,10"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
}

// docs/conformance.md U42; U130: the restarts make more measurements than PRF/PPM (§9) asks for.
TEST(UlsBehaviour, FifteenBinningTargetsRestartTheFiringSequence) {
  Unit unit(crowded_scene(15, true));
  start_crowded_binning(unit);
  unit.run(2s);
  const auto outputs = unit.firmware->outputs(unit.now);
  // Each burst stops at its 15th target, long before PPM (1 s): many measurements.
  EXPECT_GT(outputs.measurements, 40U);
  EXPECT_EQ(outputs.binning_restarts, outputs.measurements);
  const auto found = last_binning(unit.lines(universal_port));
  ASSERT_EQ(found.size(), 15U);
  for (std::size_t i = 0; i < found.size(); ++i) {
    EXPECT_EQ(found[i].count, 15);
    // The far targets beyond the 15th are never found (§3).
    EXPECT_NEAR(found[i].range.metres, 10.0 + 5.0 * static_cast<double>(i), 0.41) << i;
  }
}

// docs/conformance.md U42
TEST(UlsBehaviour, FewerThanFifteenTargetsUseTheWholeBurst) {
  Unit unit(crowded_scene(14, false));
  start_crowded_binning(unit);
  unit.run(2100ms);
  const auto outputs = unit.firmware->outputs(unit.now);
  EXPECT_EQ(outputs.measurements, 2U);  // 1000 pulses at 1000 PRF each
  EXPECT_EQ(outputs.binning_restarts, 0U);
  const auto found = last_binning(unit.lines(universal_port));
  ASSERT_EQ(found.size(), 14U);
  EXPECT_NEAR(found.back().range.metres, 75.0, 0.41);
}

// docs/conformance.md U40
TEST(UlsBehaviour, PulseWidthGrowsWithSignalAndTheSceneCanSetIt) {
  auto width_at = [](SceneTarget target) {
    Unit unit(scene_of({std::move(target)}));
    EXPECT_EQ(unit.ask("$PF,5000"), "$OK");
    EXPECT_EQ(unit.ask("$DM,3"), "$OK");
    EXPECT_EQ(unit.ask("$MO,1"), "$OK");
    EXPECT_EQ(unit.ask("$GO"), "$OK");
    const std::string line = last_line(unit);
    const MeasurementContext context{Mode::averaging, DisplayMode::intensity, Units::metres, false};
    auto m = decode_measurement(as_bytes(line), context);
    EXPECT_TRUE(m) << line;
    if (!m) return std::uint64_t{0};
    return static_cast<std::uint64_t>(std::get<AveragingReading>(m->reading).pulse_width_ps.value_or(0));
  };
  // White wall at 50 m: (266/50)^2 = 28.3 -> 4 + 6 log2(29.3) = 33.2 ns.
  const auto wall = width_at(target_at(50.0));
  EXPECT_NEAR(static_cast<double>(wall), 33'200.0, 100.0);
  EXPECT_GT(width_at(target_at(10.0)), wall);  // closer: stronger, wider
  EXPECT_LT(width_at(target_at(50.0, 0.2)), wall);
  SceneTarget sheet = target_at(1234.5, 0.9, true);
  sheet.pulse_width_ns = 2345.678;
  EXPECT_EQ(width_at(sheet), 2'345'678U);  // all 7 digits of §9's field
}

// docs/conformance.md U41
TEST(UlsBehaviour, MinimumPulseWidthRejectsNarrowReturns) {
  SceneTarget weak = target_at(12.0, 0.2);
  weak.pulse_width_ns = 5.0;
  SceneTarget wall = target_at(40.0);
  wall.pulse_width_ns = 20.0;
  Unit unit(scene_of({weak, wall}));
  EXPECT_EQ(unit.ask("$PF,5000"), "$OK");
  EXPECT_EQ(unit.ask("$DM,1"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  EXPECT_NEAR(range_of(last_line(unit)), 12.0, 0.04);  // factory 0 ns: the first return
  auto reply = unit.firmware->control({{"cmd", "min_pulse_width"}, {"ns", 10}}, unit.now);
  EXPECT_EQ(reply["ok"], true) << reply.dump();
  EXPECT_NEAR(range_of(last_line(unit)), 40.0, 0.04);  // the narrow weak return is rejected
  reply = unit.firmware->control({{"cmd", "min_pulse_width"}, {"ns", 25}}, unit.now);
  EXPECT_EQ(reply["ok"], true);
  EXPECT_EQ(last_line(unit), "$ER,4");  // every return rejected: target not found
  reply = unit.firmware->control({{"cmd", "min_pulse_width"}, {"ns", 10000}}, unit.now);
  EXPECT_NE(reply.value("error", "").find("87"), std::string::npos) << reply.dump();
  reply = unit.firmware->control({{"cmd", "min_pulse_width"}, {"ns", -1}}, unit.now);
  EXPECT_TRUE(reply.contains("error"));
  EXPECT_EQ(unit.firmware->control({{"cmd", "outputs"}}, unit.now)["min_pulse_width_ns"], 25.0);
}

// The control socket's `outputs` reports the PRF $PF holds per mode (docs/emulator-uls.md):
// §8 Set/Get PRF "$PF,a,b,c" sets the averaging, binning and look down PRFs.
TEST(UlsBehaviour, OutputsReportThePrfOfEachMode) {
  Unit unit(scene_of({target_at(12.0)}));
  EXPECT_EQ(unit.ask("$PF,1000,2000,3000"), "$OK");
  EXPECT_EQ(unit.firmware->control({{"cmd", "outputs"}}, unit.now)["prf_hz"], nlohmann::json({1000, 2000, 3000}));
  EXPECT_EQ(unit.ask("$PF,4000"), "$OK");  // one value: the current mode's (averaging)
  EXPECT_EQ(unit.firmware->control({{"cmd", "outputs"}}, unit.now)["prf_hz"], nlohmann::json({4000, 2000, 3000}));
}

// The control socket's `outputs` reports what $TT holds in pulses (docs/emulator-uls.md):
// §8 Trip Point Timeout "(seconds * 3000) in hexadecimal notation"; §3 "If the short timeout
// period is selected ... re-reference in 8,000 laser pulses" (U21: 8000 = 1F40).
// docs/conformance.md U109
TEST(UlsBehaviour, OutputsReportTheTripTimeoutInPulses) {
  Unit unit(scene_of({target_at(12.0)}));
  EXPECT_EQ(unit.ask("$TT,1F40"), "$OK");
  EXPECT_EQ(unit.firmware->control({{"cmd", "outputs"}}, unit.now)["trip_timeout_pulses"], 8000);
  EXPECT_EQ(unit.ask("$TT,107AC0"), "$OK");
  EXPECT_EQ(unit.firmware->control({{"cmd", "outputs"}}, unit.now)["trip_timeout_pulses"], 1080000);
}

// docs/conformance.md U41
TEST(UlsBehaviour, MinimumPulseWidthLetsTheUnitSeeThroughDust) {
  // Dust answers half the pulses with a 3 ns return: 992 good of 1024 cannot be filled.
  Unit unit(scene_of({target_at(30.0)}, 0.0, 0.5));
  EXPECT_EQ(unit.ask("$PF,5000"), "$OK");
  EXPECT_EQ(unit.ask("$DM,1"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  EXPECT_EQ(last_line(unit), "$ER,5");
  ASSERT_TRUE(unit.firmware->set_min_pulse_width(4.0, unit.now));
  EXPECT_NEAR(range_of(last_line(unit)), 30.0, 0.04);
}

// docs/conformance.md U39
TEST(UlsBehaviour, RangeAndIntensityLimitIs476LinesPerSecond) {
  // §9: "$BM,xxxx.xxx,yyyyyyy<CR>" is 21 characters = 2.1 ms at 115200 (U19), so the
  // fastest output is 476 Hz. A 1234.5 m reflective sheet with a 2345.678 ns return fills
  // every digit; 5000 PRF / 4 PPM asks for 1250 lines/s.
  SceneTarget sheet = target_at(1234.5, 0.9, true);
  sheet.pulse_width_ns = 2345.678;
  Unit unit(scene_of({sheet}));
  EXPECT_EQ(unit.ask("$AW,1"), "$OK");
  EXPECT_EQ(unit.ask("$PO,4"), "$OK");  // 4 pulses: a measurement without any return is 1e-8 rare
  EXPECT_EQ(unit.ask("$PF,5000"), "$OK");
  EXPECT_EQ(unit.ask("$DM,2"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(10s);
  const auto lines = unit.lines_with_times(universal_port);
  ASSERT_GT(lines.size(), 100U);
  for (const auto& line : lines) ASSERT_EQ(line.text.size() + 1, 21U) << line.text;
  // From the second line on, the UART never idles: each CR follows the last by 2.1 ms.
  for (std::size_t i = 2; i < lines.size(); ++i) ASSERT_EQ(lines[i].done - lines[i - 1].done, 2100us) << i;
  const double span = static_cast<double>((lines.back().done - lines[1].done).count()) / 1e9;
  const double rate = static_cast<double>(lines.size() - 2) / span;
  // Tolerance: the spacing is exact, so the rate is 1/2.1 ms to rounding of the span;
  // 0.1 Hz is far below the one-line-per-period steps (1250/k Hz) a skip-when-busy model gives.
  EXPECT_NEAR(rate, 476.19, 0.1);
  EXPECT_NEAR(static_cast<double>(lines.size()), 10.05 / 0.0021, 2.0);  // GO was 50 ms before the 10 s
  EXPECT_GT(unit.firmware->outputs(unit.now).skipped_lines, 0U);
}

// docs/conformance.md U36
TEST(UlsBehaviour, BaudChangeForTheOtherPortAppliesWhileItStreams) {
  // BR for the universal port sent on the configuration port, with GO right behind it:
  // the universal port starts streaming before the $OK has left, and still switches then.
  Unit unit;
  unit.send(configuration_port, "$AW,1\r$PO,2\r$PF,5000\r$DM,1\r$MO,1\r$BR,1,9600\r$GO\r");
  unit.run(1s);
  EXPECT_EQ(unit.text(configuration_port), "$OK\r$OK\r$OK\r$OK\r$OK\r$OK\r$OK\r");
  EXPECT_EQ(unit.firmware->port_settings(universal_port).baud, 9600U);
  const auto lines = unit.lines_with_times(universal_port);
  ASSERT_GT(lines.size(), 20U);
  // Saturated at 9600: each character takes 1.2 ms (U19), each line (len + CR) x 1.2 ms.
  for (std::size_t i = lines.size() - 10; i < lines.size(); ++i) {
    const auto characters = static_cast<std::int64_t>(lines[i].text.size() + 1);
    EXPECT_EQ(lines[i].done - lines[i - 1].done, Nanos(characters * 1'200'000)) << lines[i].text;
  }
}

}  // namespace
}  // namespace rangekit::uls::emulator
