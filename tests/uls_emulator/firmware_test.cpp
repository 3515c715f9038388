// The ULS firmware model driven directly on virtual time: commands, errors,
// addressing, memory, baud changes, output rate and serial limits.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "rangekit/uls/emulator/firmware.hpp"
#include "uls_emulator/helpers.hpp"

namespace rangekit::uls::emulator {
namespace {

using namespace std::chrono_literals;
using testing::Unit;

// docs/conformance.md U35
TEST(UlsFirmware, FactoryDefaultsAnswerGets) {
  Unit unit;
  EXPECT_EQ(unit.ask("$MM"), "$MM,1");
  EXPECT_EQ(unit.ask("$PF"), "$PF,2000,2000,2000");
  EXPECT_EQ(unit.ask("$PO"), "$PO,1024,1024");
  EXPECT_EQ(unit.ask("$AW"), "$AW,992");
  EXPECT_EQ(unit.ask("$BH"), "$BH,128");
  EXPECT_EQ(unit.ask("$BS"), "$BS,0");
  EXPECT_EQ(unit.ask("$TP"), "$TP,0.200");
  EXPECT_EQ(unit.ask("$AL"), "$AL,0.000");
  EXPECT_EQ(unit.ask("$AH"), "$AH,10.000");
  EXPECT_EQ(unit.ask("$AF"), "$AF,3");
  EXPECT_EQ(unit.ask("$AT"), "$AT,0");
  EXPECT_EQ(unit.ask("$MO"), "$MO,0");
  EXPECT_EQ(unit.ask("$MU"), "$MU,1");
  EXPECT_EQ(unit.ask("$DM"), "$DM,2");
  EXPECT_EQ(unit.ask("$CO"), "$CO,1");
  EXPECT_EQ(unit.ask("$TT"), "$TT,107AC0");
  EXPECT_EQ(unit.ask("$BR,0"), "$BR,0,115200");
  EXPECT_EQ(unit.ask("$BR,1"), "$BR,1,115200");
  EXPECT_EQ(unit.ask("$US"), "$US,1");
  EXPECT_EQ(unit.ask("$UA"), "$ER,82");
  EXPECT_EQ(unit.ask("$ID").substr(0, 4), "$ID,");
}

TEST(UlsFirmware, EveryErrorNumber) {
  Unit unit;
  EXPECT_EQ(unit.ask("$XY"), "$ER,1");        // unknown mnemonic
  EXPECT_EQ(unit.ask("$PT"), "$ER,1");        // PT has no get (U16)
  EXPECT_EQ(unit.ask("$MM,1.0"), "$ER,1");    // not an integer (U30)
  EXPECT_EQ(unit.ask("$PF,9"), "$ER,32");     // PRF 10-5000
  EXPECT_EQ(unit.ask("$PF,5001"), "$ER,32");  //
  EXPECT_EQ(unit.ask("$BR,0,1234"), "$ER,34");
  EXPECT_EQ(unit.ask("$AW,0"), "$ER,35");
  EXPECT_EQ(unit.ask("$PO,992"), "$ER,49");  // PPM must exceed AW
  EXPECT_EQ(unit.ask("$AW,1024"), "$ER,49");
  EXPECT_EQ(unit.ask("$AL,10"), "$ER,83");  // AL == AH
  EXPECT_EQ(unit.ask("$AF,25"), "$ER,83");
  EXPECT_EQ(unit.ask("$MO,3"), "$ER,84");
  EXPECT_EQ(unit.ask("$BR,2,9600"), "$ER,84");
  EXPECT_EQ(unit.ask("$MM,4"), "$ER,85");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  EXPECT_EQ(unit.ask("$MM,2"), "$ER,31");  // U24
  EXPECT_EQ(unit.ask("$PF,100"), "$ER,31");
  EXPECT_EQ(unit.ask("$CL,1"), "$OK");  // accepted while measuring
  EXPECT_EQ(unit.ask("$ST"), "$OK");
  EXPECT_EQ(unit.ask("$MM,2"), "$OK");
  // Settings that were refused are unchanged.
  EXPECT_EQ(unit.ask("$PF"), "$PF,2000,2000,2000");
  EXPECT_EQ(unit.ask("$AW"), "$AW,992");
}

TEST(UlsFirmware, SetsAreReadBackInUserUnits) {
  Unit unit;
  EXPECT_EQ(unit.ask("$PF,1000,500,3000"), "$OK");
  EXPECT_EQ(unit.ask("$PF"), "$PF,1000,500,3000");
  EXPECT_EQ(unit.ask("$PF,1500"), "$OK");  // the current mode's (averaging)
  EXPECT_EQ(unit.ask("$PF"), "$PF,1500,500,3000");
  EXPECT_EQ(unit.ask("$TP,1.5"), "$OK");
  EXPECT_EQ(unit.ask("$MU,0"), "$OK");
  EXPECT_EQ(unit.ask("$TP"), "$TP,4.92");  // 1.5 m in feet
  EXPECT_EQ(unit.ask("$TT,1f40"), "$OK");
  EXPECT_EQ(unit.ask("$TT"), "$TT,1F40");
  EXPECT_EQ(unit.ask("$AF,3.5"), "$OK");
  EXPECT_EQ(unit.ask("$AF"), "$AF,3.5");
}

TEST(UlsFirmware, UnitStatusFollowsModeAndMeasuring) {
  Unit unit;
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  EXPECT_EQ(unit.ask("$US"), "$US,7");
  EXPECT_EQ(unit.ask("$ST"), "$OK");
  EXPECT_EQ(unit.ask("$MM,2"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  EXPECT_EQ(unit.ask("$US"), "$US,11");
  EXPECT_EQ(unit.ask("$ST"), "$OK");
  EXPECT_EQ(unit.ask("$MM,3"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  EXPECT_EQ(unit.ask("$US"), "$US,3");
}

TEST(UlsFirmware, SaveSurvivesPowerCycleUnsavedDoesNot) {
  const auto dir = std::filesystem::temp_directory_path() / ("rangekit-uls-state-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  {
    FirmwareOptions options;
    options.state_dir = dir.string();
    Unit unit(std::move(options));
    EXPECT_EQ(unit.ask("$PF,3000"), "$OK");
    EXPECT_EQ(unit.ask("$SU"), "$OK");
    EXPECT_EQ(unit.ask("$AW,500"), "$OK");  // not saved
    unit.firmware->power_cycle(unit.now);
    EXPECT_EQ(unit.ask("$PF"), "$PF,3000,2000,2000");
    EXPECT_EQ(unit.ask("$AW"), "$AW,992");
  }
  {
    FirmwareOptions options;
    options.state_dir = dir.string();
    Unit again(std::move(options));  // a new process with the same memory
    EXPECT_EQ(again.ask("$PF"), "$PF,3000,2000,2000");
  }
  {
    // No --state: the memory outlives a power cycle of this run (U122), not the run.
    Unit volatile_unit;
    EXPECT_EQ(volatile_unit.ask("$PF,3000"), "$OK");
    EXPECT_EQ(volatile_unit.ask("$SU"), "$OK");
    volatile_unit.firmware->power_cycle(volatile_unit.now);
    EXPECT_EQ(volatile_unit.ask("$PF"), "$PF,3000,2000,2000");
    Unit next_run;
    EXPECT_EQ(next_run.ask("$PF"), "$PF,2000,2000,2000");
  }
  std::filesystem::remove_all(dir);
}

TEST(UlsFirmware, AutostartMeasuresAfterPowerUp) {
  Unit unit;
  EXPECT_EQ(unit.ask("$MA,1"), "$OK");
  EXPECT_EQ(unit.ask("$SU"), "$OK");  // no file: the memory still outlives the power cycle (U122)
  unit.firmware->power_cycle(unit.now);
  EXPECT_TRUE(unit.firmware->measuring());
  const auto dir = std::filesystem::temp_directory_path() / ("rangekit-uls-ma-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  FirmwareOptions options;
  options.state_dir = dir.string();
  Unit saved(std::move(options));
  EXPECT_EQ(saved.ask("$MA,1"), "$OK");
  EXPECT_EQ(saved.ask("$SU"), "$OK");
  saved.firmware->power_cycle(saved.now);
  EXPECT_TRUE(saved.firmware->measuring());
  saved.run(1s);
  EXPECT_FALSE(saved.lines(configuration_port).empty());
  std::filesystem::remove_all(dir);
}

// docs/conformance.md U36
TEST(UlsFirmware, BaudChangeTakesEffectAfterTheOk) {
  Unit unit;
  unit.send(universal_port, "$BR,1,9600\r");
  // The $OK still leaves at 115200 ...
  EXPECT_EQ(unit.firmware->port_settings(universal_port).baud, 115200U);
  unit.run(3ms);  // 11 request bytes at 115200, the 1 ms turnaround, "$OK\r"
  EXPECT_EQ(unit.text(universal_port), "$OK\r");
  // ... and the port runs at 9600 from then on.
  EXPECT_EQ(unit.firmware->port_settings(universal_port).baud, 9600U);
  EXPECT_EQ(unit.firmware->port_settings(configuration_port).baud, 115200U);
  unit.send(universal_port, "$MM\r");
  const Nanos sent = unit.now;
  unit.run(20ms);
  const auto bytes = unit.take(universal_port);
  ASSERT_EQ(bytes.size(), 6U);
  // "$MM\r" crosses the line (4 bytes of 10 bits at 9600), the unit turns round (1 ms, U133),
  // then "$MM,1\r" leaves at 1.2 ms a character (U19).
  const Nanos request = 4 * Nanos(10'000'000'000LL / 9600);
  EXPECT_EQ(bytes.back().done - sent, request + 1ms + 6 * 1200us);
  EXPECT_EQ(unit.ask("$BR,1"), "$BR,1,9600");
}

// U126: §2 Output Setup "the measurement data and control will then be directed to that port for
// output", "The RS232 configuration port is always active as an input": with the factory MO 0 the
// universal port still takes a command and answers it there.
TEST(UlsFirmware, RepliesGoToThePortTheCommandCameFrom) {
  Unit unit;
  unit.send(universal_port, "$MM\r");
  unit.run(2ms);
  EXPECT_EQ(unit.text(universal_port), "$MM,1\r");
  EXPECT_EQ(unit.text(configuration_port), "");
}

// docs/conformance.md U37
TEST(UlsFirmware, AddressedBroadcastAndUnassigned) {
  FirmwareOptions options;
  options.address = 'Z';
  Unit unit(std::move(options));
  EXPECT_EQ(unit.ask("#ZMM", universal_port), "#ZMM,1");
  EXPECT_EQ(unit.ask("#ZUA", universal_port), "#ZUA,90");
  EXPECT_EQ(unit.ask("#YMM", universal_port), "");  // another unit's
  EXPECT_EQ(unit.ask("#ZPF,1", universal_port), "#ZER,32");
  EXPECT_EQ(unit.ask("\xF0MM,2", universal_port), "");   // not a frame at all
  EXPECT_EQ(unit.ask("#\xF0MM,2", universal_port), "");  // broadcast: acts, no reply
  EXPECT_EQ(unit.ask("#ZMM", universal_port), "#ZMM,2");
  EXPECT_EQ(unit.ask("#ZUA,Y", universal_port), "#ZOK");  // the reply still comes from Z
  EXPECT_EQ(unit.ask("#ZMM", universal_port), "");
  EXPECT_EQ(unit.ask("#YMM", universal_port), "#YMM,2");
  EXPECT_EQ(unit.ask("$UA", universal_port), "$UA,89");

  Unit unassigned;  // factory address 0 (U3)
  EXPECT_EQ(unassigned.ask("#0MM", universal_port), "");
  EXPECT_EQ(unassigned.ask("$MM", universal_port), "$MM,1");
  EXPECT_EQ(unassigned.ask("$UA,A", universal_port), "$OK");
  EXPECT_EQ(unassigned.ask("#AMM", universal_port), "#AMM,1");
}

// docs/conformance.md U37
TEST(UlsFirmware, MalformedDollarFramesAnswerErrorOne) {
  Unit unit;
  EXPECT_EQ(unit.ask("$MM,"), "$ER,1");
  EXPECT_EQ(unit.ask("garbage"), "");
}

TEST(UlsFirmware, OutputRateIsPrfOverPpmOverSixtySeconds) {
  Unit unit;
  EXPECT_EQ(unit.ask("$AW,7"), "$OK");
  EXPECT_EQ(unit.ask("$PO,48"), "$OK");
  EXPECT_EQ(unit.ask("$PF,4999"), "$OK");  // 104.1458... Hz: not a whole number of ns per pulse
  EXPECT_EQ(unit.ask("$DM,1"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");  // stream on the universal port
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  const Nanos start = unit.now - 50ms;  // ask() ran 50 ms after the GO
  unit.run(60s - 50ms);
  const auto lines = unit.lines_with_times(universal_port);
  const double expected_hz = 4999.0 / 48.0;
  ASSERT_EQ(lines.size(), static_cast<std::size_t>(60.0 * expected_hz));  // 6248
  const double span = static_cast<double>((lines.back().done - lines.front().done).count()) / 1e9;
  const double rate = static_cast<double>(lines.size() - 1) / span;
  EXPECT_LT(std::abs(rate - expected_hz) / expected_hz, 1e-4) << rate;
  // Every line leaves exactly k x PPM / PRF after the start plus its own transmission time.
  const Nanos line_time = Nanos(static_cast<std::int64_t>(lines.back().text.size() + 1) * 100'000);
  const auto k = static_cast<std::int64_t>(lines.size());
  EXPECT_EQ(lines.back().done - start - line_time, Nanos(k * 48 * 1'000'000'000LL / 4999));
}

// Fastest line rate when a measurement completes every `period` and a line takes `line`:
// one measurement waits behind the line on the wire (U39), so a saturated port sends
// back to back; slower measurements go out as they come.
double paced_rate(double period_s, double line_s) { return 1.0 / std::max(period_s, line_s); }

// docs/conformance.md U38, U39
TEST(UlsFirmware, SerialLimitsEmergeFromPacing) {
  // 5000 PRF / 2 PPM asks for 2500 lines/s; "$BM,150.000<CR>" is 12 characters
  // = 1.2 ms at 115200 (U19), so the port carries 833 lines/s (§9).
  Scene scene;
  scene.targets.push_back(SceneTarget{"far", Motion::fixed(150.0), 0.9, true});
  FirmwareOptions options;
  options.scene = scene;
  Unit unit(std::move(options));
  EXPECT_EQ(unit.ask("$AW,1"), "$OK");
  EXPECT_EQ(unit.ask("$PO,2"), "$OK");
  EXPECT_EQ(unit.ask("$PF,5000"), "$OK");
  EXPECT_EQ(unit.ask("$DM,1"), "$OK");
  EXPECT_EQ(unit.ask("$MO,1"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  unit.run(10s);
  auto lines = unit.lines_with_times(universal_port);
  ASSERT_GT(lines.size(), 2U);
  EXPECT_EQ(lines[1].text.size() + 1, 12U) << lines[1].text;  // with its CR
  double rate =
      static_cast<double>(lines.size() - 2) / (static_cast<double>((lines.back().done - lines[1].done).count()) / 1e9);
  EXPECT_NEAR(rate, 833.33, 0.5);
  // Range and pulse width: longer lines, fewer of them; the rate is set by the line time.
  EXPECT_EQ(unit.ask("$ST"), "$OK");
  EXPECT_EQ(unit.ask("$DM,2"), "$OK");
  EXPECT_EQ(unit.ask("$GO"), "$OK");
  (void)unit.take(universal_port);
  unit.run(10s);
  lines = unit.lines_with_times(universal_port);
  ASSERT_GT(lines.size(), 2U);
  const std::size_t characters = lines[1].text.size() + 1;
  rate =
      static_cast<double>(lines.size() - 2) / (static_cast<double>((lines.back().done - lines[1].done).count()) / 1e9);
  EXPECT_NEAR(rate, paced_rate(2.0 / 5000.0, static_cast<double>(characters) * 100e-6), 0.5) << lines[1].text;
  EXPECT_GT(unit.firmware->outputs(unit.now).skipped_lines, 0U);
}

}  // namespace
}  // namespace rangekit::uls::emulator
