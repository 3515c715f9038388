// Readings of the document revisited in issue 12 (docs/conformance.md U75-U81): the
// cooperative range, the feet round trip of every setting, and the §10 errors 25, 31,
// 33 and 78, and the fault current before the first distance of a run. Expectations
// are typed from the document.
#include <gtest/gtest.h>

#include <string>
#include <variant>

#include "rangekit/uls/uls.hpp"
#include "uls/emulator/firmware.hpp"
#include "uls_emulator/helpers.hpp"

namespace rangekit::uls::emulator {
namespace {

using namespace std::chrono_literals;
using testing::Unit;

FirmwareOptions with_target(SceneTarget target) {
  FirmwareOptions options;
  options.scene.targets = {std::move(target)};
  options.scene.ambient_noise = 0.5;
  options.seed = 42;
  return options;
}

// Range-only lines on the universal port, 0.2 s apart (1024 pulses at 5000 Hz).
void start_fast_averaging(Unit& unit) {
  EXPECT_EQ(unit.ask("$PF,5000"), "$OK");
  EXPECT_EQ(unit.ask("$DM,1"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
}

// The range of a range-only averaging line, -1 if it has none.
double metres_of(const std::string& line) {
  const MeasurementContext context{Mode::averaging, DisplayMode::range, Units::metres, false};
  auto m = decode_measurement(as_bytes(line), context);
  if (!m) return -1;
  const auto* reading = std::get_if<AveragingReading>(&m->reading);
  return reading && reading->range ? reading->range->metres : -1;
}

// docs/conformance.md U75. §9 Averaging Mode, "Maximum Cooperative Range": "1700 m or 5577 ft
// (High-intensity Reflective Sheet)" in each of the Maximum, Medium and Minimum columns.
TEST(UlsReadings, U75_CooperativeRangeIs1700MetresAtEveryPowerLevel) {
  Unit unit(with_target(SceneTarget{"sheet", Motion::fixed(1600.0), 0.9, true}));
  for (const char* power : {"0", "1", "2"}) {
    SCOPED_TRACE(power);
    EXPECT_EQ(unit.ask(std::string("$PL,") + power), "$OK");
    start_fast_averaging(unit);
    unit.run(1s);
    const auto lines = unit.lines(universal_port);
    ASSERT_FALSE(lines.empty());
    EXPECT_NEAR(metres_of(lines.back()), 1600.0, 0.02) << lines.back();  // "±2 cm typical" cooperative (§9)
    EXPECT_EQ(unit.ask("$ST"), "$OK");
    (void)unit.take(universal_port);
  }
  // Beyond 1700 m nothing answers, at any power.
  unit.firmware->move_target(0, 1750.0, unit.now);
  EXPECT_EQ(unit.ask("$PL,0"), "$OK");
  start_fast_averaging(unit);
  unit.run(1s);
  const auto lines = unit.lines(universal_port);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.back(), "$ER,4");
}

}  // namespace
}  // namespace rangekit::uls::emulator
