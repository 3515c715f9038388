// Readings of the document (docs/conformance.md U75-U81): the cooperative range, the feet
// round trip of every setting, §10 errors 25, 31, 33 and 78, and the fault current before
// a run's first distance. Expectations are typed from the document.
#include <gtest/gtest.h>

#include <string>
#include <variant>

#include "rangekit/uls/emulator/firmware.hpp"
#include "rangekit/uls/uls.hpp"
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

using testing::metres_of;

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

// Every get+set setting: the values its get reports, sent back as a set, answer $OK. UA is
// left out: §8 sets it with "aa = unit address (Ascii single character)" and reports
// "ad = unit Address (Decimal Value)".
void expect_every_get_accepted_back(Unit& unit) {
  for (const CommandInfo& command : command_table()) {
    if (command.access != Access::get_set || command.mnemonic == "UA") continue;
    const std::string name(command.mnemonic);
    const std::string reply = unit.ask("$" + name + (name == "BR" ? ",1" : ""));
    ASSERT_EQ(reply.rfind("$" + name + ",", 0), 0U) << reply;
    EXPECT_EQ(unit.ask(reply), "$OK") << "set back: " << reply;
  }
}

// docs/conformance.md U76. §8 "n = Long Gate Setting in measurement units", §9 "Resolution:
// 0.01 ft or 1 mm" and "1700 m or 5577 ft": at the limits a get in feet reads 5577.43
// (1700 / 0.3048 = 5577.427), and the unit takes back whatever it reports, in both units.
TEST(UlsReadings, U76_EveryValueAGetReportsIsAcceptedBackInBothUnitsAtTheLimits) {
  Unit unit;
  for (const bool feet : {false, true}) {
    SCOPED_TRACE(feet ? "feet" : "metres");
    EXPECT_EQ(unit.ask(feet ? "$MU,0" : "$MU,1"), "$OK");
    const std::string top = feet ? "5577.43" : "1700.000";
    EXPECT_EQ(unit.ask("$AH,10"), "$OK");  // AL and AH must differ (83): move them apart first
    EXPECT_EQ(unit.ask("$AL,0"), "$OK");
    for (const char* mnemonic : {"SG", "LG", "TP", "OF", "AH"}) {
      EXPECT_EQ(unit.ask("$" + std::string(mnemonic) + "," + top), "$OK") << mnemonic;
      EXPECT_EQ(unit.ask("$" + std::string(mnemonic)), "$" + std::string(mnemonic) + "," + top);
    }
    expect_every_get_accepted_back(unit);
    // The other ends: gates at 0, OF at -1700 m, AL at the top and AH at 0.
    for (const char* mnemonic : {"SG", "LG", "TP"}) EXPECT_EQ(unit.ask("$" + std::string(mnemonic) + ",0"), "$OK");
    EXPECT_EQ(unit.ask("$OF,-" + top), "$OK");
    EXPECT_EQ(unit.ask("$OF"), "$OF,-" + top);
    EXPECT_EQ(unit.ask("$AH,10"), "$OK");
    EXPECT_EQ(unit.ask("$AL," + top), "$OK");
    EXPECT_EQ(unit.ask("$AH,0"), "$OK");
    expect_every_get_accepted_back(unit);
  }
  // A limit set in one unit is that limit in the other.
  EXPECT_EQ(unit.ask("$MU,0"), "$OK");
  EXPECT_EQ(unit.ask("$LG,5577.43"), "$OK");
  EXPECT_EQ(unit.ask("$OF,-5577.43"), "$OK");
  EXPECT_EQ(unit.ask("$MU,1"), "$OK");
  EXPECT_EQ(unit.ask("$LG"), "$LG,1700.000");
  EXPECT_EQ(unit.ask("$OF"), "$OF,-1700.000");
  EXPECT_EQ(unit.ask("$SG,1700"), "$OK");
  EXPECT_EQ(unit.ask("$MU,0"), "$OK");
  EXPECT_EQ(unit.ask("$SG"), "$SG,5577.43");
  // One step beyond, in either unit, is still refused (U18).
  EXPECT_EQ(unit.ask("$LG,5577.44"), "$ER,1");
  EXPECT_EQ(unit.ask("$OF,5577.44"), "$ER,1");
  EXPECT_EQ(unit.ask("$AH,5577.44"), "$ER,83");
  EXPECT_EQ(unit.ask("$MU,1"), "$OK");
  EXPECT_EQ(unit.ask("$LG,1700.001"), "$ER,1");
}

// docs/conformance.md U77. §10 31 "No Serial While Measuring Error", displayed "Instrument Is
// Already Measuring"; the counterpart of 86 "Instrument Not Measuring" for ST (U43).
TEST(UlsReadings, U77_StartWhileMeasuringIsErrorThirtyOne) {
  FirmwareOptions options = with_target(SceneTarget{"wall", Motion::fixed(25.0), 0.9, false});
  options.address = 'Z';
  Unit unit(std::move(options));
  start_fast_averaging(unit);
  unit.run(1s);
  const std::uint64_t before = unit.firmware->outputs(unit.now).measurements;
  EXPECT_EQ(unit.ask("$GO"), "$ER,31");
  EXPECT_EQ(unit.ask("#ZGO"), "#ZER,31");
  EXPECT_EQ(unit.ask("$US"), "$US,7");  // still measuring, not restarted
  unit.run(1s);
  EXPECT_GT(unit.firmware->outputs(unit.now).measurements, before + 3);
  EXPECT_EQ(unit.ask("$ST"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
}

// docs/conformance.md U78. §10 25 "RX Buffer Overrun"; F5: frames are at most 64 bytes before
// the CR. A longer line is answered once its CR arrives, like a refused frame (U37).
TEST(UlsReadings, U78_LineOverTheFrameLimitIsRxBufferOverrun) {
  FirmwareOptions options;
  options.address = 'Z';
  Unit unit(std::move(options));
  const std::string sixty(60, 'A');
  EXPECT_EQ(unit.ask("$ID," + sixty), "$ER,1");           // 64 bytes: a frame, refused by the parser
  EXPECT_EQ(unit.ask("$ID," + sixty + "A"), "$ER,25");    // 65 bytes
  EXPECT_EQ(unit.ask("$ID," + sixty + sixty), "$ER,25");  // the rest of the line is lost with it
  EXPECT_EQ(unit.ask("$MM"), "$MM,1");                    // and the next line is read as usual
  EXPECT_EQ(unit.ask("#ZID," + sixty, universal_port), "#ZER,25");
  EXPECT_EQ(unit.ask("#YID," + sixty, universal_port), "");     // another unit's
  EXPECT_EQ(unit.ask("#\xF0ID," + sixty, universal_port), "");  // broadcast: no reply (U4)
  // A start byte before the CR cuts the long line short (F3): only the new frame is answered.
  EXPECT_EQ(unit.ask("$ID," + sixty + sixty + "$MM"), "$MM,1");
  // A control byte makes it noise (F4): no answer.
  EXPECT_EQ(unit.ask("$ID," + sixty + sixty + "\n" + "A"), "");
  EXPECT_EQ(unit.ask("$MM"), "$MM,1");
}

// docs/conformance.md U79. §2 "Pulses/Measure ... this option is not available in the Look Down
// Mode"; §10 78 "Invalid Command for Measurement Mode". One value sets the current mode's PPM
// (U15), which look down does not have; the two-value form names averaging and binning.
TEST(UlsReadings, U79_OneValuePulsesPerMeasurementInLookDownIsErrorSeventyEight) {
  Unit unit;
  EXPECT_EQ(unit.ask("$MM,3"), "$OK");
  EXPECT_EQ(unit.ask("$PO,500"), "$ER,78");
  EXPECT_EQ(unit.ask("$PO"), "$PO,1024,1024");
  EXPECT_EQ(unit.ask("$PO,2000,500"), "$OK");
  EXPECT_EQ(unit.ask("$PO"), "$PO,2000,500");
  EXPECT_EQ(unit.ask("$MM,2"), "$OK");
  EXPECT_EQ(unit.ask("$PO,600"), "$OK");  // binning's
  EXPECT_EQ(unit.ask("$PO"), "$PO,2000,600");
}

// docs/conformance.md U80. §8 TT "h = Trip Point Timeout ((seconds * 3000) in hexadecimal
// notation)"; §10 33 "Invalid Input Base".
TEST(UlsReadings, U80_TripTimeoutNotInHexIsInvalidInputBase) {
  Unit unit;
  EXPECT_EQ(unit.ask("$TT,1G40"), "$ER,33");
  EXPECT_EQ(unit.ask("$TT,3.5"), "$ER,33");
  EXPECT_EQ(unit.ask("$TT,123456789"), "$ER,1");  // 9 digits (U18)
  EXPECT_EQ(unit.ask("$TT"), "$TT,107AC0");       // unchanged
  EXPECT_EQ(unit.ask("$TB,A"), "$ER,1");          // TB is a 0/1 flag (§8)
  EXPECT_EQ(unit.ask("$TT,1F40"), "$OK");
}

// docs/conformance.md U81. §8 AT "n = Fault Timeout (in seconds, timeout allowed before 4-20mA goes
// to the fault current indication)"; §6 "Fault current will be output when error 4 or 5 exists".
// The timeout applies also when no distance has been measured since the GO.
TEST(UlsReadings, U81_FaultTimeoutAppliesBeforeTheFirstDistanceOfARun) {
  Unit unit(with_target(SceneTarget{"wall", Motion::fixed(50.0), 0.9, false}));
  EXPECT_EQ(unit.ask("$CL,1"), "$OK");
  EXPECT_EQ(unit.ask("$AH,100"), "$OK");
  EXPECT_EQ(unit.ask("$AT,1"), "$OK");
  unit.firmware->set_no_return_fault(true, unit.now);
  start_fast_averaging(unit);  // 50 ms into the run
  unit.run(450ms);             // errors 4 from 0.2 s: 0.3 s of errors, AT not over
  EXPECT_EQ(unit.firmware->outputs(unit.now).last_error, 4);
  EXPECT_DOUBLE_EQ(unit.firmware->outputs(unit.now).current_ma, 4.0);  // nothing to hold yet
  unit.run(1s);
  EXPECT_DOUBLE_EQ(unit.firmware->outputs(unit.now).current_ma, 3.0);  // AF (§6 "3.0 mA")
  // A distance of an earlier run is not held in a new one.
  EXPECT_EQ(unit.ask("$ST"), "$OK");
  unit.firmware->set_no_return_fault(false, unit.now);
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(1s);
  EXPECT_NEAR(unit.firmware->outputs(unit.now).current_ma, 12.0, 0.01);  // 50 m of 0-100 m (§6)
  EXPECT_EQ(unit.ask("$ST"), "$OK");
  unit.firmware->set_no_return_fault(true, unit.now);
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(450ms);
  EXPECT_DOUBLE_EQ(unit.firmware->outputs(unit.now).current_ma, 4.0);
  unit.run(1s);
  EXPECT_DOUBLE_EQ(unit.firmware->outputs(unit.now).current_ma, 3.0);
}

}  // namespace
}  // namespace rangekit::uls::emulator
