// Measurement physics of the ULS model (docs/conformance.md U38) on a fixed seed: averaging accuracy
// (§9), binning against averaging (§3 figure), look-down latency (§3), the
// 4-20 mA loop (§6), polled output and the scene file.
#include <gtest/gtest.h>

#include <cmath>

#include "rangekit/uls/emulator/firmware.hpp"
#include "rangekit/uls/uls.hpp"
#include "uls_emulator/helpers.hpp"

namespace rangekit::uls::emulator {
namespace {

using namespace std::chrono_literals;
using testing::Unit;

FirmwareOptions with_targets(std::vector<SceneTarget> targets, double noise = 0.5) {
  FirmwareOptions options;
  options.scene.targets = std::move(targets);
  options.scene.ambient_noise = noise;
  options.seed = 42;
  return options;
}

std::vector<double> averaging_ranges(Unit& unit, std::size_t count) {
  std::vector<double> ranges;
  const MeasurementContext context{Mode::averaging, DisplayMode::range, Units::metres, false};
  while (ranges.size() < count) {
    unit.run(1s);
    for (const auto& line : unit.lines(universal_port)) {
      auto m = decode_measurement(as_bytes(line), context);
      EXPECT_TRUE(m) << "[" << line << "] " << (m ? "" : m.error().message);
      if (!m) continue;
      const auto* reading = std::get_if<AveragingReading>(&m->reading);
      EXPECT_NE(reading, nullptr) << line;
      if (reading && reading->range) ranges.push_back(reading->range->metres);
    }
  }
  return ranges;
}

using testing::metres_of;

void setup_fast_averaging(Unit& unit) {
  EXPECT_EQ(unit.ask("$PF,5000"), "$OK");
  EXPECT_EQ(unit.ask("$DM,1"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
}

TEST(UlsPhysics, AveragingWithinFourCentimetresNonCooperative) {
  Unit unit(with_targets({SceneTarget{"wall", Motion::fixed(87.654), 0.5, false}}));
  setup_fast_averaging(unit);
  const auto ranges = averaging_ranges(unit, 1000);
  for (const double r : ranges) ASSERT_NEAR(r, 87.654, 0.04);
}

// U128 (kept): §3 dithering "can dramatically increase the accuracy of the measurement"; in this
// model the single-pulse jitter already spreads returns over the timing grid, so dithering keeps
// the §9 "±4 cm typical" but gains nothing measurable. Both ways stay within it.
// U129 (kept): §2 "This value should be a multiple of 32": advice, so AW 100 is taken with DD on.
TEST(UlsPhysics, DitheringKeepsTheAveragingWithinFourCentimetresU128U129) {
  for (const char* averaging_weight : {"$AW,32", "$AW,100"}) {
    for (const char* dither : {"$DD,0", "$DD,1"}) {
      Unit unit(with_targets({SceneTarget{"wall", Motion::fixed(87.654), 0.5, false}}));
      EXPECT_EQ(unit.ask(averaging_weight), "$OK");
      EXPECT_EQ(unit.ask(dither), "$OK");
      setup_fast_averaging(unit);
      const auto ranges = averaging_ranges(unit, 200);
      for (const double r : ranges) ASSERT_NEAR(r, 87.654, 0.04) << averaging_weight << " " << dither;
    }
  }
}

TEST(UlsPhysics, AveragingWithinTwoCentimetresCooperative) {
  Unit unit(with_targets({SceneTarget{"prism", Motion::fixed(612.345), 0.9, true}}));
  EXPECT_EQ(unit.ask("$FL,1"), "$OK");
  setup_fast_averaging(unit);
  const auto ranges = averaging_ranges(unit, 1000);
  for (const double r : ranges) ASSERT_NEAR(r, 612.345, 0.02);
}

TEST(UlsPhysics, OffsetFeetAndMaximumRange) {
  Unit unit(with_targets({SceneTarget{"gray", Motion::fixed(120.0), 0.2, false}}));
  EXPECT_EQ(unit.ask("$OF,1.5"), "$OK");
  EXPECT_EQ(unit.ask("$PL,1"), "$OK");  // medium power: 114 m on 20% gray (§9)
  setup_fast_averaging(unit);
  unit.run(1s);
  auto lines = unit.lines(universal_port);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.back(), "$ER,4");  // target not found
  EXPECT_EQ(unit.ask("$ST"), "$OK");
  EXPECT_EQ(unit.ask("$PL,0"), "$OK");  // high power: 133 m
  EXPECT_EQ(unit.ask("$MU,0"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(1s);
  lines = unit.lines(universal_port);
  ASSERT_FALSE(lines.empty());
  const MeasurementContext feet{Mode::averaging, DisplayMode::range, Units::feet, false};
  auto m = decode_measurement(as_bytes(lines.back()), feet);
  ASSERT_TRUE(m) << lines.back();
  EXPECT_NEAR(std::get<AveragingReading>(m->reading).range->metres, 121.5, 0.04);
}

TEST(UlsPhysics, AverageNotFilledAndTargetNotFound) {
  Unit unit(with_targets({SceneTarget{"wall", Motion::fixed(30.0), 0.9, false}}));
  unit.firmware->set_scene(Scene{{SceneTarget{"wall", Motion::fixed(30.0), 0.9, false}}, 0.5, 0.5}, unit.now);
  setup_fast_averaging(unit);  // dust blocks half the pulses: 992 of 1024 cannot be filled
  unit.run(1s);
  auto lines = unit.lines(universal_port);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.back(), "$ER,5");
  unit.firmware->set_no_return_fault(true, unit.now);
  unit.firmware->set_scene(Scene{{SceneTarget{"wall", Motion::fixed(30.0), 0.9, false}}, 0.0, 0.5}, unit.now);
  unit.run(1s);
  lines = unit.lines(universal_port);
  EXPECT_EQ(lines.back(), "$ER,4");
}

TEST(UlsPhysics, BinningSeesTheWeakFarTargetAveragingMisses) {
  // §3 figure: a near white target and a far gray one beyond the averaging threshold.
  Unit unit(with_targets(
      {SceneTarget{"near", Motion::fixed(40.0), 0.9, false}, SceneTarget{"far", Motion::fixed(200.0), 0.2, false}}));
  setup_fast_averaging(unit);
  const auto ranges = averaging_ranges(unit, 5);
  for (const double r : ranges) EXPECT_NEAR(r, 40.0, 0.04);
  EXPECT_EQ(unit.ask("$ST"), "$OK");
  EXPECT_EQ(unit.ask("$MM,2"), "$OK");
  EXPECT_EQ(unit.ask("$BS,5"), "$OK");  // 32 inches: 416 m
  EXPECT_EQ(unit.ask("$PF,1000"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  (void)unit.take(universal_port);
  unit.run(3s);
  const auto lines = unit.lines(universal_port);
  ASSERT_GE(lines.size(), 2U);
  const MeasurementContext context{Mode::binning, DisplayMode::range, Units::metres, false};
  std::vector<BinningTarget> last;
  for (const auto& line : lines) {
    auto m = decode_measurement(as_bytes(line), context);
    ASSERT_TRUE(m) << line;
    const auto target = std::get<BinningTarget>(m->reading);
    if (target.index == 0) last.clear();
    last.push_back(target);
  }
  ASSERT_EQ(last.size(), 2U);
  EXPECT_EQ(last[0].count, 2);
  EXPECT_NEAR(last[0].range.metres, 40.0, 0.82);  // one 32-inch bin
  EXPECT_NEAR(last[1].range.metres, 200.0, 0.82);
  EXPECT_GE(last[1].strength, 128U);
}

// How many of `bursts` binning measurements find a target within one bin of `distance_m`.
int bursts_finding(Unit& unit, double distance_m, int bursts) {
  const MeasurementContext context{Mode::binning, DisplayMode::range, Units::metres, false};
  (void)unit.take(universal_port);
  unit.run(std::chrono::milliseconds(1100 * bursts));  // PPM 1024 at PRF 1000: 1.024 s a burst
  int found = 0;
  int completed = 0;
  bool this_burst = false;
  for (const auto& line : unit.lines(universal_port)) {
    auto m = decode_measurement(as_bytes(line), context);
    EXPECT_TRUE(m) << line;
    if (!m) continue;
    const auto* target = std::get_if<BinningTarget>(&m->reading);
    if (target && target->index == 0) this_burst = false;
    if (target && std::abs(target->range.metres - distance_m) < 1.7 && !this_burst) {
      this_burst = true;  // one per burst, whatever its index
      ++found;
    }
    if (!target || target->index + 1 == target->count) ++completed;
    if (completed == bursts) break;
  }
  EXPECT_GE(completed, bursts);
  return found;
}

// U125. §9 Binning Mode "Maximum Range 450 m to white wall 90% diffuse / 300 m / 250 m",
// "225 m to gray wall 20% diffuse / 150 m / 125 m" (Maximum, Medium, Minimum power), with
// the factory Bin Hits 128 and PPM 1024 at PRF 1000.
TEST(UlsPhysics, BinningReachesTheRangesOfSection9AndNotBeyondU125) {
  struct Limit {
    const char* power;  // §8 PL: 0 high, 1 medium, 2 low
    double reflectivity;
    double range_m;
  };
  const Limit limits[] = {{"0", 0.9, 450.0}, {"1", 0.9, 300.0}, {"2", 0.9, 250.0},
                          {"0", 0.2, 225.0}, {"1", 0.2, 150.0}, {"2", 0.2, 125.0}};
  constexpr int bursts = 20;
  for (const Limit& limit : limits) {
    for (const double share : {0.95, 1.12}) {
      const double d = limit.range_m * share;
      Unit unit(with_targets({SceneTarget{"wall", Motion::fixed(d), limit.reflectivity, false}}));
      EXPECT_EQ(unit.ask("$MM,2"), "$OK");
      EXPECT_EQ(unit.ask("$BS,6"), "$OK");  // 64-inch bins: 832 m, past every limit
      EXPECT_EQ(unit.ask(std::string("$PL,") + limit.power), "$OK");
      EXPECT_EQ(unit.ask("$PF,1000"), "$OK");
      EXPECT_EQ(unit.ask("$MO,1"), "$OK");
      EXPECT_EQ(unit.ask("$GO"), "$OK");
      const int found = bursts_finding(unit, d, bursts);
      SCOPED_TRACE(std::string("PL ") + limit.power + ", " + std::to_string(d) + " m");
      if (share < 1) {
        EXPECT_GE(found, 15) << "of " << bursts;  // most
      } else {
        EXPECT_LE(found, 1) << "of " << bursts;  // none or almost none
      }
    }
  }
}

TEST(UlsPhysics, BinningStopsAtFifteenTargets) {
  // Bin hits too low: noise bins become targets, at most 15 (§3).
  Unit unit(with_targets({SceneTarget{"wall", Motion::fixed(10.0), 0.9, false}}, 20.0));
  EXPECT_EQ(unit.ask("$MM,2"), "$OK");
  EXPECT_EQ(unit.ask("$BH,30"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(2s);
  const auto lines = unit.lines(universal_port);
  ASSERT_FALSE(lines.empty());
  EXPECT_NE(lines.back().find(",15,"), std::string::npos) << lines.back();
}

TEST(UlsPhysics, LookDownTripsAfterThirtyPulses) {
  Unit unit(with_targets({SceneTarget{"ground", Motion::fixed(8.0), 0.5, false}}));
  EXPECT_EQ(unit.ask("$MM,3"), "$OK");
  EXPECT_EQ(unit.ask("$PF,3000,3000,3000"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(1s);
  EXPECT_TRUE(unit.lines(universal_port).empty());  // reference taken, display blank (§3)
  // A vehicle arrives at 1.5 m under the unit.
  Scene scene;
  scene.targets = {SceneTarget{"ground", Motion::fixed(8.0), 0.5, false},
                   SceneTarget{"truck", Motion::fixed(6.5), 0.5, false}};
  const Nanos arrival = unit.now;
  unit.firmware->set_scene(scene, arrival);
  unit.run(100ms);
  auto lines = unit.lines_with_times(universal_port);
  ASSERT_EQ(lines.size(), 1U);
  EXPECT_EQ(lines[0].text, "$BM,1");
  const Nanos decided = lines[0].done - 6 * 100us;  // "$BM,1<CR>" takes 6 characters
  EXPECT_GE(decided - arrival, Nanos(29 * 1'000'000'000LL / 3000));
  EXPECT_LE(decided - arrival, Nanos(31 * 1'000'000'000LL / 3000));  // 10 ms ± 1 pulse (U34)
  EXPECT_TRUE(unit.firmware->outputs(unit.now).trip);
  unit.firmware->set_scene(Scene{{SceneTarget{"ground", Motion::fixed(8.0), 0.5, false}}, 0, 0.5}, unit.now);
  unit.run(100ms);
  lines = unit.lines_with_times(universal_port);
  ASSERT_EQ(lines.size(), 1U);
  EXPECT_EQ(lines[0].text, "$BM,0");
}

TEST(UlsPhysics, LookDownReReferencesAfterTripTimeout) {
  Unit unit(with_targets({SceneTarget{"ground", Motion::fixed(8.0), 0.5, false}}));
  EXPECT_EQ(unit.ask("$MM,3"), "$OK");
  EXPECT_EQ(unit.ask("$PF,3000,3000,3000"), "$OK");
  EXPECT_EQ(unit.ask("$TT,1F40"), "$OK");  // short timeout: 8000 pulses
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(1s);
  unit.firmware->set_scene(Scene{{SceneTarget{"ground", Motion::fixed(8.0), 0.5, false},
                                  SceneTarget{"parked", Motion::fixed(6.0), 0.5, false}},
                                 0,
                                 0.5},
                           unit.now);
  unit.run(2s);
  EXPECT_EQ(unit.lines(universal_port), std::vector<std::string>{"$BM,1"});
  unit.run(2s);  // 8000 pulses = 2.67 s after the trip: the parked car is the new reference
  EXPECT_EQ(unit.lines(universal_port), std::vector<std::string>{"$BM,0"});
}

TEST(UlsPhysics, TimeBetweenEventsCountsPulses) {
  Unit unit(with_targets({SceneTarget{"ground", Motion::fixed(8.0), 0.5, false}}));
  EXPECT_EQ(unit.ask("$MM,3"), "$OK");
  EXPECT_EQ(unit.ask("$PF,3000,3000,3000"), "$OK");
  EXPECT_EQ(unit.ask("$TB,1"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(1s);
  const Scene ground{{SceneTarget{"ground", Motion::fixed(8.0), 0.5, false}}, 0, 0.5};
  Scene car = ground;
  car.targets.push_back(SceneTarget{"car", Motion::fixed(6.0), 0.5, false});
  unit.firmware->set_scene(car, unit.now);
  unit.run(500ms);
  unit.firmware->set_scene(ground, unit.now);
  unit.run(1s);  // 1 s of no presence = 3000 pulses (0BB8, §3)
  unit.firmware->set_scene(car, unit.now);
  unit.run(500ms);
  // §3 "can be logged using the configuration port only": not on MO's universal port (U74).
  EXPECT_TRUE(unit.lines(universal_port).empty());
  const auto lines = unit.lines(configuration_port);
  ASSERT_EQ(lines.size(), 3U);
  EXPECT_EQ(lines[1], "$0");
  EXPECT_EQ(lines[2], "$0BB8");
}

TEST(UlsPhysics, CurrentLoopFollowsDistanceThenFaults) {
  Unit unit(with_targets({SceneTarget{"wall", Motion::fixed(50.0), 0.9, false}}));
  EXPECT_EQ(unit.firmware->outputs(unit.now).current_ma, 0.0);
  EXPECT_EQ(unit.ask("$CL,1"), "$OK");
  EXPECT_EQ(unit.ask("$AH,100"), "$OK");
  EXPECT_EQ(unit.ask("$AT,1"), "$OK");
  EXPECT_EQ(unit.firmware->outputs(unit.now).current_ma, 0.0);  // not measuring
  setup_fast_averaging(unit);
  unit.run(1s);
  EXPECT_NEAR(unit.firmware->outputs(unit.now).current_ma, 12.0, 0.01);
  unit.firmware->set_no_return_fault(true, unit.now);
  unit.run(500ms);
  EXPECT_NEAR(unit.firmware->outputs(unit.now).current_ma, 12.0, 0.01);  // held until AT
  unit.run(1s);
  EXPECT_DOUBLE_EQ(unit.firmware->outputs(unit.now).current_ma, 3.0);
}

TEST(UlsPhysics, PolledOutputAndGetMeasurementStartsTheUnit) {
  Unit unit(with_targets({SceneTarget{"wall", Motion::fixed(25.0), 0.9, false}}));
  EXPECT_EQ(unit.ask("$CO,0"), "$OK");
  EXPECT_EQ(unit.ask("$DM,1"), "$OK");
  unit.send(configuration_port, "$BM\r");  // idle: starts measuring, answers with the first result
  EXPECT_TRUE(unit.firmware->measuring());
  unit.run(1s);
  auto lines = unit.lines(configuration_port);
  ASSERT_EQ(lines.size(), 1U);
  EXPECT_NEAR(metres_of(lines[0]), 25.0, 0.04) << lines[0];
  unit.run(2s);
  EXPECT_TRUE(unit.lines(configuration_port).empty());  // polled: nothing streams
  EXPECT_NEAR(metres_of(unit.ask("$BM")), 25.0, 0.04);  // the latest
}

TEST(UlsPhysics, MeasurementsGoToTheSelectedPortInTheUnitsForm) {
  FirmwareOptions options = with_targets({SceneTarget{"wall", Motion::fixed(25.0), 0.9, false}});
  options.address = 'Q';
  Unit unit(std::move(options));
  EXPECT_EQ(unit.ask("$DM,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(1s);
  EXPECT_NEAR(metres_of(unit.lines(configuration_port).back()), 25.0, 0.04);
  EXPECT_EQ(unit.ask("$ST"), "$OK");
  EXPECT_EQ(unit.ask("$MO,2"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(1s);
  EXPECT_TRUE(unit.lines(configuration_port).empty());
  const std::string addressed = unit.lines(universal_port).back();
  EXPECT_EQ(addressed.substr(0, 4), "#QBM") << addressed;
  EXPECT_NEAR(metres_of(addressed), 25.0, 0.04) << addressed;
}

TEST(UlsScene, ParsesTargetsAndMotion) {
  const auto scene = parse_scene(R"(
dust = 0.01
ambient_noise = 2
[[targets]]
name = "wall"
distance_m = 120.5
reflectivity = 0.2
[[targets]]
distance_m = 10
speed_mps = 1.5
cooperative = true
[[targets]]
path = [[0, 5], [10, 25]]
)",
                                 "scene.toml");
  ASSERT_TRUE(scene) << scene.error().message;
  ASSERT_EQ(scene->targets.size(), 3U);
  EXPECT_EQ(scene->targets[0].name, "wall");
  EXPECT_DOUBLE_EQ(scene->targets[0].reflectivity, 0.2);
  EXPECT_TRUE(scene->targets[1].cooperative);
  EXPECT_DOUBLE_EQ(scene->targets[1].motion.position_at(2s), 13.0);
  EXPECT_DOUBLE_EQ(scene->targets[2].motion.position_at(5s), 15.0);
  EXPECT_DOUBLE_EQ(scene->dust, 0.01);
  EXPECT_DOUBLE_EQ(scene->ambient_noise, 2.0);
}

TEST(UlsScene, ErrorsNameFileLineAndKey) {
  auto bad = parse_scene("[[targets]]\ndistance_m = 10\nreflectivity = 1.5\n", "scene.toml");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("scene.toml:3: 'reflectivity'"), std::string::npos) << bad.error().message;
  bad = parse_scene("[[targets]]\ndistnce_m = 10\n", "s.toml");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("s.toml:2: 'distnce_m': unknown key"), std::string::npos) << bad.error().message;
  bad = parse_scene("[[targets]]\nname = \"x\"\n", "s.toml");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("needs 'distance_m' or 'path'"), std::string::npos) << bad.error().message;
  bad = parse_scene("dust = [\n", "broken.toml");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("broken.toml:"), std::string::npos) << bad.error().message;
  auto json = scene_from_json(nlohmann::json::parse(R"({"targets":[{"distance_m":12,"cooperative":true}]})"));
  ASSERT_TRUE(json) << json.error().message;
  EXPECT_TRUE(json->targets[0].cooperative);
}

}  // namespace
}  // namespace rangekit::uls::emulator
