// Look down as §3 and §8 describe it, seen from the serial ports:
// a Get Measurement poll in look down (U70-U72), the re-reference release with time between
// events on (U73) and the port time between events is logged on (U74).
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "rangekit/uls/emulator/firmware.hpp"
#include "rangekit/uls/uls.hpp"
#include "uls_emulator/helpers.hpp"

namespace rangekit::uls::emulator {
namespace {

using namespace std::chrono_literals;
using testing::Unit;

const SceneTarget look_down_ground{"ground", Motion::fixed(8.0), 0.5, false};

SceneTarget vehicle_at(double metres) { return SceneTarget{"vehicle", Motion::fixed(metres), 0.5, false}; }

Scene look_down_scene(std::vector<SceneTarget> targets) {
  Scene scene;
  scene.targets = std::move(targets);
  scene.ambient_noise = 0;
  return scene;
}

FirmwareOptions looking_at_the_ground() {
  FirmwareOptions options;
  options.scene = look_down_scene({look_down_ground});
  options.seed = 11;
  return options;
}

// Pulses of a `$XXXX` line (§8: "XXXX = Time between no presence and presence detected in hex"),
// -1 when the line is not four hex digits after the `$`.
long tbe_pulses(const std::string& line) {
  if (line.size() != 5 || line[0] != '$') return -1;
  char* end = nullptr;
  const long pulses = std::strtol(line.c_str() + 1, &end, 16);
  return *end == '\0' ? pulses : -1;
}

// U70: §8 Get Measurement "Reply: Varies with measurement mode"; look down answers
// "$BM,n<CR> ... n = 0 = OFF, N = 1 = ON". A poll is answered once, at once, with the state now.
TEST(UlsLookDown, U70_PollIsAnsweredAtOnceWithTheTripState) {
  FirmwareOptions options = looking_at_the_ground();
  options.address = 'Q';
  Unit unit(std::move(options));
  EXPECT_EQ(unit.ask("$MM,3"), "$OK");
  EXPECT_EQ(unit.ask("$CO,0"), "$OK");  // polled (§8 CO 0)
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(1s);
  EXPECT_EQ(unit.ask("$BM"), "$BM,0");  // nothing moving: OFF, one line
  EXPECT_EQ(unit.ask("#QBM"), "#QBM,0");
  unit.firmware->set_scene(look_down_scene({look_down_ground, vehicle_at(6.5)}), unit.now);
  unit.run(1s);
  // Polled: the trip sends nothing by itself (no poll is left waiting for it).
  EXPECT_TRUE(unit.lines(configuration_port).empty());
  EXPECT_TRUE(unit.lines(universal_port).empty());
  EXPECT_EQ(unit.ask("$BM"), "$BM,1");  // §3 "ON is displayed when the system is tripped"
  EXPECT_EQ(unit.ask("$BM"), "$BM,1");  // each poll its own answer
  unit.firmware->set_scene(look_down_scene({look_down_ground}), unit.now);
  unit.run(1s);
  EXPECT_EQ(unit.ask("$BM"), "$BM,0");
  unit.run(1s);
  EXPECT_TRUE(unit.lines(configuration_port).empty());
}

// U71: §3 Note "The display will remain blank when the system is first started and the
// reference is detected." The stream stays silent until the first detection; a poll before it
// answers the trip line, which is low ("'no target detected' ... will be a low state"): OFF.
TEST(UlsLookDown, U71_PollBeforeTheFirstDetectionAnswersOff) {
  Unit unit(looking_at_the_ground());
  EXPECT_EQ(unit.ask("$MM,3"), "$OK");
  EXPECT_EQ(unit.ask("$PF,10"), "$OK");  // look down at 10 Hz: the reference takes 30 pulses = 3 s
  // §2 ULS Autostart: Get Measurement starts an idle unit; it answers before any reference.
  EXPECT_EQ(unit.ask("$BM"), "$BM,0");
  EXPECT_TRUE(unit.firmware->measuring());
  unit.run(5s);  // reference taken, nothing detected: the continuous output stays blank
  EXPECT_TRUE(unit.lines(configuration_port).empty());
  EXPECT_TRUE(unit.lines(universal_port).empty());
  EXPECT_EQ(unit.ask("$BM"), "$BM,0");
}

// U72: §8 look down "When Time between Events is turned on: $n<CR> output at the start of no
// presence detected; $XXXX<CR> output at the start of presence detected". A poll answers the
// line of the state now: `$0` without presence, the present presence's `$XXXX` with it.
TEST(UlsLookDown, U72_PollWithTimeBetweenEventsAnswersTheCurrentEvent) {
  Unit unit(looking_at_the_ground());
  EXPECT_EQ(unit.ask("$MM,3"), "$OK");
  EXPECT_EQ(unit.ask("$PF,3000"), "$OK");
  EXPECT_EQ(unit.ask("$CO,0"), "$OK");
  EXPECT_EQ(unit.ask("$TB,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(1s);
  EXPECT_EQ(unit.ask("$BM"), "$0");  // "n = 0 = OFF = No Presence detected"
  const Scene car = look_down_scene({look_down_ground, vehicle_at(6.0)});
  unit.firmware->set_scene(car, unit.now);
  unit.run(500ms);
  unit.firmware->set_scene(look_down_scene({look_down_ground}), unit.now);
  unit.run(1s);  // §3: "a value of 0BB8 hex (3000 decimal) would be output if the time between
                 // not present edge to present edge was detected that equaled 1 second" (3 kHz)
  unit.firmware->set_scene(car, unit.now);
  unit.run(500ms);
  EXPECT_EQ(unit.ask("$BM"), "$0BB8");
  EXPECT_EQ(unit.ask("$BM"), "$0BB8");  // still the same presence
  unit.firmware->set_scene(look_down_scene({look_down_ground}), unit.now);
  unit.run(500ms);
  EXPECT_EQ(unit.ask("$BM"), "$0");
  EXPECT_TRUE(unit.lines(configuration_port).empty());  // polled: nothing else was sent
  EXPECT_TRUE(unit.lines(universal_port).empty());
}

// U73: §3 "If the trip signal is in its active state, and the ULS registers a target distance
// that does not change for prolonged time ... it will establish this distance as the new
// reference distance"; "the unit will re-reference in 8,000 laser pulses" (short timeout). The
// trip ends, so §8's "$n ... output at the start of no presence detected" is sent, and the next
// `$XXXX` counts "fire pulses between not present and present events" from that release.
TEST(UlsLookDown, U73_ReReferenceWithTimeBetweenEventsStartsTheNoPresenceTime) {
  Unit unit(looking_at_the_ground());
  EXPECT_EQ(unit.ask("$MM,3"), "$OK");
  EXPECT_EQ(unit.ask("$PF,3000"), "$OK");
  EXPECT_EQ(unit.ask("$TT,1F40"), "$OK");  // 8000 pulses = 2.67 s at 3000 PRF
  EXPECT_EQ(unit.ask("$TB,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(1s);
  const SceneTarget parked = vehicle_at(6.0);
  unit.firmware->set_scene(look_down_scene({look_down_ground, parked}), unit.now);
  unit.run(2s);
  const auto tripped = unit.lines(configuration_port);
  ASSERT_EQ(tripped.size(), 1U);
  EXPECT_GT(tbe_pulses(tripped[0]), 0) << tripped[0];  // the presence edge of the parked car
  // 8000 pulses (2.67 s) after the trip the parked car is the reference: within the next second.
  unit.run(1s);
  const auto released = unit.lines_with_times(configuration_port);
  ASSERT_EQ(released.size(), 1U);
  EXPECT_EQ(released[0].text, "$0");
  EXPECT_FALSE(unit.firmware->outputs(unit.now).trip);
  // "$0<CR>" is 3 characters of 100 µs at 115200 (§9, U19): the release was 300 µs before.
  const Nanos release = released[0].done - 300us;
  ASSERT_GT(release + 1s, unit.now);
  unit.run(release + 1s - unit.now);
  unit.firmware->set_scene(look_down_scene({look_down_ground, parked, vehicle_at(4.0)}), unit.now);
  unit.run(500ms);
  const auto next = unit.lines(configuration_port);
  ASSERT_EQ(next.size(), 1U);
  // 1 s of no presence at 3 kHz is 3000 pulses (§3), plus at most the 30 pulses that decide
  // the trip (§3 "the sensor uses 30 laser pulses"); counting from the parked car's arrival
  // instead would add its 8000 parked pulses.
  EXPECT_GE(tbe_pulses(next[0]), 3000) << next[0];
  EXPECT_LE(tbe_pulses(next[0]), 3031) << next[0];
}

// U74: §3 "Time between events can be logged using the configuration port only" against §4
// "When the ULS is in Look Down Mode, the configuration port is used for system setup only."
// The §3 sentence is about time between events itself, so it wins: with TB on the lines go to
// the configuration port whatever MO selects; `$BM,0/1` (TB off) follows MO as before.
TEST(UlsLookDown, U74_TimeBetweenEventsIsLoggedOnTheConfigurationPortOnly) {
  FirmwareOptions options = looking_at_the_ground();
  options.address = 'Q';
  Unit unit(std::move(options));
  EXPECT_EQ(unit.ask("$MM,3"), "$OK");
  EXPECT_EQ(unit.ask("$PF,3000"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");  // measurements to the universal port (RS232)
  EXPECT_EQ(unit.ask("$TB,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(1s);
  unit.firmware->set_scene(look_down_scene({look_down_ground, vehicle_at(6.0)}), unit.now);
  unit.run(500ms);
  unit.firmware->set_scene(look_down_scene({look_down_ground}), unit.now);
  unit.run(500ms);
  const auto logged = unit.lines(configuration_port);
  ASSERT_EQ(logged.size(), 2U);
  EXPECT_GT(tbe_pulses(logged[0]), 0) << logged[0];
  EXPECT_EQ(logged[1], "$0");
  EXPECT_TRUE(unit.lines(universal_port).empty());

  EXPECT_EQ(unit.ask("$ST"), "$OK");
  EXPECT_EQ(unit.ask("$TB,0"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(1s);
  unit.firmware->set_scene(look_down_scene({look_down_ground, vehicle_at(6.0)}), unit.now);
  unit.run(500ms);
  EXPECT_EQ(unit.lines(universal_port), std::vector<std::string>{"$BM,1"});
  EXPECT_TRUE(unit.lines(configuration_port).empty());

  // RS-485 output with an address: the configuration port is RS-232, point to point, so the
  // logged lines keep the `$` form there.
  EXPECT_EQ(unit.ask("$ST"), "$OK");
  EXPECT_EQ(unit.ask("$MO,2"), "$OK");
  EXPECT_EQ(unit.ask("$TB,1"), "$OK");
  unit.firmware->set_scene(look_down_scene({look_down_ground}), unit.now);
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(1s);
  unit.firmware->set_scene(look_down_scene({look_down_ground, vehicle_at(6.0)}), unit.now);
  unit.run(500ms);
  const auto addressed = unit.lines(configuration_port);
  ASSERT_EQ(addressed.size(), 1U);
  EXPECT_GT(tbe_pulses(addressed[0]), 0) << addressed[0];
  EXPECT_TRUE(unit.lines(universal_port).empty());
}

}  // namespace
}  // namespace rangekit::uls::emulator
