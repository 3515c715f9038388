// Every command of table 9.1 against the firmware model, byte for byte.
// Conformance rows held here: L26 (no reply to what the sensor cannot honour), L27 (DF in RAM),
// L28 (serial settings after the echo), L37 (any byte stops the stream), L39 (OF), L50 and L84 (the
// combined value, checked on the pair), L51 (ports 0001-FFFF), L52 (no zero period, exposure, fixed range),
// L53 (analog output disabled holds), L55 (DF and the network address), L83 (DF restarts the timer),
// L92 (the sync input while off).
#include <unistd.h>

#include <utility>

#include "ls5_emulator/firmware_rig.hpp"

namespace rangekit::ls5::emulator::testing {
namespace {

TEST(Ls5Commands, IdentificationHasThe35CharacterField) {
  FirmwareConfig config = test_config("LS5.6.0");
  config.lower_boundary_mm = 8.1234;
  config.range_mm = 40.001;
  Rig rig(config);
  EXPECT_EQ(rig.exchange("#01ID\r"), "%01LS5.6.0   b8,1234d40,0010s/n0000157\r");
}

TEST(Ls5Commands, Section94SessionsByteForByte) {
  Rig first;
  EXPECT_EQ(first.exchange("#01ON\r"), "!01ON\r");
  FirmwareConfig config = test_config();
  config.factory_address = 0x02;
  Rig second(config);
  EXPECT_EQ(second.exchange("#02W0B01\r"), "!02W0B01\r");
  EXPECT_EQ(second.fw->ram(0x0B), 0x01);
}

TEST(Ls5Commands, ReadReturnsTheTableDefaults) {
  Rig rig;
  EXPECT_EQ(rig.exchange("#01R06\r"), "!01R0664\r");
  EXPECT_EQ(rig.exchange("#01R0D\r"), "!01R0D05\r");
  EXPECT_EQ(rig.exchange("#01R65\r"), "!01R659D\r");  // MAC low byte: serial 157 = 0x9D (L20)
}

TEST(Ls5Commands, InvalidWriteAndUnknownAddressGetNoReplyAndChangeNothing) {
  Rig rig;
  EXPECT_EQ(rig.exchange("#01W0D02\r"), "");  // median points must be odd
  EXPECT_EQ(rig.fw->ram(0x0D), 0x05);
  EXPECT_EQ(rig.exchange("#01W0800\r"), "");  // thinning 0
  EXPECT_EQ(rig.exchange("#01R7F\r"), "");    // no such parameter
  EXPECT_EQ(rig.exchange("#01W7F00\r"), "");
  EXPECT_EQ(rig.exchange("#01XX\r"), "");               // not a command
  EXPECT_EQ(rig.exchange("#01W13FF\r"), "!01W13FF\r");  // 14 = C3: first of a pair, held (L84)
  EXPECT_EQ(rig.exchange("#01W14C3\r"), "");            // the pair C3FF = 50175, above 50000
  EXPECT_EQ(rig.fw->ram(0x13), 0x50);                   // undone with it
  EXPECT_EQ(rig.exchange("#01R06\r"), "!01R0664\r");    // still answering
}

TEST(Ls5Commands, Table93ByteOrderAndTheReverseBothReachTheValueL84) {
  // Table 9.3 writes a value low byte first: "The upper limit of the analog output is 50000
  // (0xC350)": "#01W1350<cr> #01W14C3<cr>". §8.10: "The values of the lower and upper bounds
  // can only be in the range 0÷50000": checked on the value the pair makes.
  Rig rig;  // upper limit 13/14 = 50 C3 = 50000
  // 50000 -> 25000 (0x61A8) in table 9.3's order: C3A8 = 50088 until the high byte follows.
  EXPECT_EQ(rig.exchange("#01W13A8\r"), "!01W13A8\r");
  EXPECT_EQ(rig.exchange("#01R13\r"), "!01R13A8\r");  // RAM holds what was written
  rig.set_scene_code(40000);                          // meanwhile the limit acts as 50000: 4 + 16 × 40000 / 50000 mA
  rig.run_for(10ms);
  EXPECT_DOUBLE_EQ(rig.fw->analog_value(), 16.8);
  EXPECT_EQ(rig.exchange("#01W1461\r"), "!01W1461\r");
  EXPECT_EQ(rig.fw->ram(0x13) | rig.fw->ram(0x14) << 8, 25000);
  rig.set_scene_code(12500);
  rig.run_for(10ms);
  EXPECT_DOUBLE_EQ(rig.fw->analog_value(), 12.0);  // 4 + 16 × 12500 / 25000
  // 25000 -> 50000 and back to 25000 in the reverse order, high byte first.
  rig.write(0x14, 0xC3);  // C3A8 = 50088: held
  rig.write(0x13, 0x50);
  EXPECT_EQ(rig.fw->ram(0x13) | rig.fw->ram(0x14) << 8, 50000);
  rig.write(0x14, 0x61);  // 6150 = 24912, in range at once
  rig.write(0x13, 0xA8);
  EXPECT_EQ(rig.fw->ram(0x13) | rig.fw->ram(0x14) << 8, 25000);

  // Table 9.3 in full, from the defaults: every write echoed.
  Rig table;
  const std::pair<std::uint8_t, std::uint8_t> table_93[] = {
      {0x15, 0x12}, {0x16, 0x20}, {0x17, 0x4E}, {0x18, 0x40}, {0x19, 0x9C}, {0x1A, 0x10}, {0x1B, 0x27},
      {0x1C, 0x30}, {0x1D, 0x75}, {0x03, 0x01}, {0x11, 0x00}, {0x12, 0x00}, {0x13, 0x50}, {0x14, 0xC3}};
  for (const auto& [address, value] : table_93) table.write(address, value);
  EXPECT_EQ(table.fw->ram(0x18) | table.fw->ram(0x19) << 8, 40000);  // "equals 40000 (0x9C40)"
  EXPECT_EQ(table.fw->ram(0x1C) | table.fw->ram(0x1D) << 8, 30000);  // "equals 30000 (0x7530)"
}

TEST(Ls5Commands, APairThatEndsOutOfRangeIsRefusedAsAWholeL84) {
  // §8.10/§8.11: limits and swings "can only be in the range 0÷50000".
  Rig rig;
  EXPECT_EQ(rig.exchange("#01W13FF\r"), "!01W13FF\r");  // C3FF: held
  EXPECT_EQ(rig.exchange("#01W1351\r"), "!01W1351\r");  // the same byte again: C351, still held
  EXPECT_EQ(rig.exchange("#01W14C3\r"), "");            // the pair C351 = 50001: no reply
  EXPECT_EQ(rig.exchange("#01R13\r"), "!01R1350\r");    // and the first byte is undone
  EXPECT_EQ(rig.exchange("#01R14\r"), "!01R14C3\r");
  // A byte that brings the pair back in range ends the wait: 18 = FF held, then 18 = 40 (C340).
  EXPECT_EQ(rig.exchange("#01W18FF\r"), "!01W18FF\r");
  rig.write(0x18, 0x40);
  rig.write(0x19, 0x9C);  // 9C40 = 40000, in range: taken
  EXPECT_EQ(rig.fw->ram(0x18) | rig.fw->ram(0x19) << 8, 40000);
  // FL stores a half-written pair at the value it acts with; power-up brings that back.
  EXPECT_EQ(rig.exchange("#01W1CFF\r"), "!01W1CFF\r");  // C3FF: held
  EXPECT_EQ(rig.exchange("#01FL\r"), "!01FL\r");
  EXPECT_EQ(rig.fw->rom(0x1C), 0x50);
  rig.fw->power_cycle(rig.now);
  EXPECT_EQ(rig.exchange("#01R1C\r"), "!01R1C50\r");
  // DF forgets a held byte with the rest: the lower limit acts as 0 again, not as the 255 held.
  EXPECT_EQ(rig.exchange("#01W11FF\r"), "!01W11FF\r");  // 00FF: in range
  EXPECT_EQ(rig.exchange("#01W12C3\r"), "!01W12C3\r");  // C3FF: held, the limit acts as 255
  EXPECT_EQ(rig.exchange("#01DF\r"), "!01DF\r");
  rig.set_scene_code(25000);
  rig.run_for(10ms);
  EXPECT_DOUBLE_EQ(rig.fw->analog_value(), 12.0);  // 4 + 16 × 25000 / 50000
}

TEST(Ls5Commands, EveryWriteInTheCodecsWriteOrderIsAcceptedL50) {
  // The host writes split_value_in_write_order's bytes; the firmware must take every one of them.
  Rig rig;
  const auto& lower = logical_value_info(LogicalValueId::analog_lower_limit);
  for (const std::uint64_t value : {25000, 50000, 0, 20000, 50000, 49999, 0x00FF, 0xC300, 0xC350, 1}) {
    auto writes = split_value_in_write_order(lower, value);
    ASSERT_TRUE(writes.ok()) << writes.error().message;
    for (const auto& write : writes->view()) rig.write(write.address, write.value);
    EXPECT_EQ(rig.fw->ram(0x11) | rig.fw->ram(0x12) << 8, static_cast<int>(value));
  }
  const auto& period = logical_value_info(LogicalValueId::measurement_period);
  for (const std::uint64_t value : {0x0100, 0x0001, 0xFF00, 0x0200, 0x0064}) {
    auto writes = split_value_in_write_order(period, value);
    ASSERT_TRUE(writes.ok()) << writes.error().message;
    for (const auto& write : writes->view()) rig.write(write.address, write.value);
    EXPECT_EQ(rig.fw->ram(0x06) | rig.fw->ram(0x07) << 8, static_cast<int>(value));
  }
}

TEST(Ls5Commands, PortsWithALowByte00CanBeSetL51) {
  // Table 9.2, destination port: "For the parameter itself: 0001-FFFF".
  Rig rig;                                              // destination port 02 5B = 603
  EXPECT_EQ(rig.exchange("#01W6D00\r"), "!01W6D00\r");  // 0x0200 = 512
  rig.write(0x6C, 0x04);                                // 0x0400 = 1024
  EXPECT_EQ(rig.exchange("#01R6D\r"), "!01R6D00\r");
  EXPECT_EQ(rig.exchange("#01R6C\r"), "!01R6C04\r");
  EXPECT_EQ(rig.exchange("#01W6C00\r"), "!01W6C00\r");  // port 0 unless 6D follows: held (L84)
  EXPECT_EQ(rig.exchange("#01W6D00\r"), "");            // port 0: refused, 6C undone
  EXPECT_EQ(rig.exchange("#01R6C\r"), "!01R6C04\r");
  EXPECT_EQ(rig.exchange("#01W6F00\r"), "!01W6F00\r");  // source port 0x1300 = 4864
}

TEST(Ls5Commands, ZeroPeriodExposureAndFixedRangesAreIgnoredL52) {
  // Table 9.2: measurement period, maximum exposure time, fixed range of the analog output and of
  // the discrete outputs: "For the parameter itself: 0001-FFFF".
  // A 00 that makes one of them 0 is held as the first byte of a pair (L84); the pair ending at
  // 0 is refused and undoes it.
  Rig rig(test_config("LS5.9.0"));
  EXPECT_EQ(rig.exchange("#01W0600\r"), "!01W0600\r");  // period 00 00 unless 07 follows
  EXPECT_EQ(rig.exchange("#01W0700\r"), "");
  rig.write(0x21, 0x00);  // exposure 00B8 = 184 µs
  EXPECT_EQ(rig.exchange("#01W2000\r"), "!01W2000\r");
  EXPECT_EQ(rig.exchange("#01W2100\r"), "");
  rig.write(0x24, 0x00);  // 0010
  EXPECT_EQ(rig.exchange("#01W2300\r"), "!01W2300\r");
  EXPECT_EQ(rig.exchange("#01W2400\r"), "");
  rig.write(0x26, 0x00);
  EXPECT_EQ(rig.exchange("#01W2500\r"), "!01W2500\r");
  EXPECT_EQ(rig.exchange("#01W2600\r"), "");
  EXPECT_EQ(rig.fw->ram(0x06), 0x64);
  EXPECT_EQ(rig.fw->ram(0x20), 0xB8);
  EXPECT_EQ(rig.fw->ram(0x23), 0x10);
  EXPECT_EQ(rig.fw->ram(0x25), 0x10);
  // The period still measures every 10 ms.
  const auto count = rig.fw->measurements();
  rig.run_for(100ms);
  EXPECT_EQ(rig.fw->measurements(), count + 10);
  // τ = 0 is allowed: "for τ = 0 ms parameter is 0000".
  rig.write(0x09, 0x00);
}

TEST(Ls5Commands, FeaturesBeyondTheVersionAreRefused) {
  Rig old(test_config("LS5.8.0"));
  EXPECT_EQ(old.exchange("#01W1F02\r"), "");  // latching with recalculation needs LS5.9.0
  EXPECT_EQ(old.exchange("#01R70\r"), "");    // Ethernet parameters need LS5.12
  EXPECT_EQ(old.exchange("#01W1F01\r"), "!01W1F01\r");
  Rig older(test_config("LS5.5.0"));
  EXPECT_EQ(older.exchange("#01W0506\r"), "");  // 230400 needs LS5.6.0
  EXPECT_EQ(older.exchange("#01R22\r"), "");    // priority needs LS5.7.0
}

TEST(Ls5Commands, BroadcastActsWithoutReplyAndOtherAddressesAreIgnored) {
  Rig rig;
  EXPECT_EQ(rig.exchange("#00W0B01\r"), "");
  EXPECT_EQ(rig.fw->ram(0x0B), 0x01);
  EXPECT_EQ(rig.exchange("#00OF\r"), "");
  EXPECT_FALSE(rig.fw->laser_on());
  EXPECT_EQ(rig.exchange("#02ON\r"), "");
  EXPECT_FALSE(rig.fw->laser_on());
  EXPECT_EQ(rig.exchange("#00ID\r"), "");  // not a broadcast command (L15)
}

TEST(Ls5Commands, StoreToFlashSurvivesPowerCyclePlainWriteDoesNot) {
  FirmwareConfig config = test_config();
  config.state_dir = temp_dir("flash");
  {
    Rig rig(config);
    rig.write(0x0C, 0x04);
    EXPECT_EQ(rig.exchange("#01FL\r"), "!01FL\r");
    rig.write(0x08, 0x03);  // not stored
    rig.fw->power_cycle(rig.now);
    EXPECT_EQ(rig.exchange("#01R0C\r"), "!01R0C04\r");
    EXPECT_EQ(rig.exchange("#01R08\r"), "!01R0801\r");
  }
  Rig restarted(config);  // a new process with the same --state DIR
  EXPECT_EQ(restarted.exchange("#01R0C\r"), "!01R0C04\r");
  std::filesystem::remove_all(config.state_dir);
}

TEST(Ls5Commands, RestoreDefaultsChangesRamOnlyUntilFlash) {
  Rig rig;
  rig.write(0x0C, 0x04);
  EXPECT_EQ(rig.exchange("#01FL\r"), "!01FL\r");
  EXPECT_EQ(rig.exchange("#01DF\r"), "!01DF\r");
  EXPECT_EQ(rig.exchange("#01R0C\r"), "!01R0C01\r");
  EXPECT_EQ(rig.fw->rom(0x0C), 0x04);
  rig.fw->power_cycle(rig.now);
  EXPECT_EQ(rig.exchange("#01R0C\r"), "!01R0C04\r");
}

TEST(Ls5Commands, RestoreDefaultsRunsTheTimerAtTheDefaultPeriodAtOnceL83) {
  // §8.13: "When triggered by an internal timer, the sensor measures according to the set
  // parameter "The sensor measurement period"". Table 9.2: triggering 1E default 00 "by timer";
  // period 06/07 default 64 00 "(corresponds 10 ms)".
  Rig rig;
  rig.write(0x1E, 0x01);  // by the sync input: no timer
  auto count = rig.fw->measurements();
  rig.run_for(100ms);
  EXPECT_EQ(rig.fw->measurements(), count);
  EXPECT_EQ(rig.exchange("#01DF\r"), "!01DF\r");  // 20 ms: the timer's first two measurements
  EXPECT_EQ(rig.fw->measurements(), count + 2);
  EXPECT_EQ(rig.exchange("#01R1E\r"), "!01R1E00\r");
  count = rig.fw->measurements();
  rig.run_for(100ms);
  EXPECT_EQ(rig.fw->measurements(), count + 10);

  // 6553.5 ms (FFFF), then DF: 10 ms again from the DF on, not after the 6.5 s already begun.
  rig.write(0x06, 0xFF);
  rig.write(0x07, 0xFF);
  count = rig.fw->measurements();
  EXPECT_EQ(rig.exchange("#01DF\r"), "!01DF\r");
  EXPECT_EQ(rig.fw->measurements(), count + 2);
  EXPECT_EQ(rig.exchange("#01R06\r"), "!01R0664\r");
  count = rig.fw->measurements();
  rig.run_for(100ms);
  EXPECT_EQ(rig.fw->measurements(), count + 10);
}

TEST(Ls5Commands, RestoreDefaultsSetsTheNetworkAddressTo01L55) {
  // Table 9.2: network address, default 01; §8.1: "The initial address set at the manufacturer is 01."
  FirmwareConfig config = test_config();
  config.factory_address = 0x05;  // delivered set to 05 (--address 5)
  Rig rig(config);
  EXPECT_EQ(rig.exchange("#05R01\r"), "!05R0105\r");
  EXPECT_EQ(rig.exchange("#05DF\r"), "!05DF\r");  // echoed at the address it was sent to
  EXPECT_EQ(rig.exchange("#05R01\r"), "");
  EXPECT_EQ(rig.exchange("#01R01\r"), "!01R0101\r");
  // RAM only (L27): a power cycle brings back the address in ROM ...
  rig.fw->power_cycle(rig.now);
  EXPECT_EQ(rig.exchange("#05R01\r"), "!05R0105\r");
  // ... unless FL stored it.
  EXPECT_EQ(rig.exchange("#05DF\r"), "!05DF\r");
  EXPECT_EQ(rig.exchange("#01FL\r"), "!01FL\r");
  rig.fw->power_cycle(rig.now);
  EXPECT_EQ(rig.exchange("#01R01\r"), "!01R0101\r");
}

TEST(Ls5Commands, LastResultBeforeTheFirstMeasurementIsNoMeasurementYet) {
  Rig rig;
  rig.send("#01LR\r");
  rig.run_for(5ms);  // first measurement after one period (10 ms)
  EXPECT_EQ(rig.out, "!01LR65534\r");
  rig.run_for(10ms);
  EXPECT_EQ(rig.exchange("#01LR\r"), "!01LR25000\r");
}

TEST(Ls5Commands, LatchAndReadLatched) {
  Rig rig;
  EXPECT_EQ(rig.exchange("#01FR\r"), "!01FR65534\r");
  EXPECT_EQ(rig.exchange("#01FX\r"), "!01FX\r");
  rig.set_scene_code(30000);
  EXPECT_EQ(rig.exchange("#01FR\r"), "!01FR25000\r");
  EXPECT_EQ(rig.exchange("#01LR\r"), "!01LR30000\r");
}

TEST(Ls5Commands, OffStopsMeasuringZeroesDiscreteOutputsAndHoldsAnalog) {
  Rig rig;
  rig.write(0x15, 0x11);  // both outputs enabled, N = 0: 1 inside the swings
  rig.write(0x16, 0x00);
  rig.write(0x17, 0x00);
  rig.write(0x18, 0x50);
  rig.write(0x19, 0xC3);
  rig.run_for(20ms);
  EXPECT_TRUE(rig.fw->output1());
  const double analog = rig.fw->analog_value();
  EXPECT_EQ(rig.exchange("#01OF\r"), "!01OF\r");
  const auto count = rig.fw->measurements();
  rig.set_scene_code(40000);
  rig.run_for(100ms);
  EXPECT_EQ(rig.fw->measurements(), count);
  EXPECT_FALSE(rig.fw->output1());
  EXPECT_FALSE(rig.fw->output2());
  EXPECT_DOUBLE_EQ(rig.fw->analog_value(), analog);
  EXPECT_EQ(rig.exchange("#01ON\r"), "!01ON\r");
  rig.run_for(20ms);
  EXPECT_GT(rig.fw->measurements(), count);
}

TEST(Ls5Commands, ASyncEdgeWhileOffNeitherMeasuresNorLatchesL92) {
  // §8.13: "The measurement process with subsequent latching will be triggered by the rising edge
  // of the signal at the synchronization input, regardless of what operations were performed
  // before in the sensor." §8.2: when off, "there is no irradiation of the measured object ...
  // and no measurements are made. The sensor scans the network only for commands."
  Rig rig;  // latching 01 (table 9.2 default): an edge measures and latches
  rig.run_for(20ms);
  auto count = rig.fw->measurements();
  rig.fw->set_sync_input(true, rig.now);
  rig.fw->set_sync_input(false, rig.now);
  EXPECT_EQ(rig.fw->measurements(), count + 1);
  EXPECT_EQ(rig.exchange("#01FR\r"), "!01FR25000\r");
  EXPECT_EQ(rig.exchange("#01OF\r"), "!01OF\r");
  rig.set_scene_code(40000);
  count = rig.fw->measurements();
  rig.fw->set_sync_input(true, rig.now);
  rig.fw->set_sync_input(false, rig.now);
  EXPECT_EQ(rig.fw->measurements(), count);
  EXPECT_EQ(rig.exchange("#01FR\r"), "!01FR25000\r");  // the latch keeps what it had
  EXPECT_EQ(rig.exchange("#01ON\r"), "!01ON\r");
  rig.fw->set_sync_input(true, rig.now);
  rig.fw->set_sync_input(false, rig.now);
  EXPECT_EQ(rig.exchange("#01FR\r"), "!01FR40000\r");
}

TEST(Ls5Commands, DisabledAnalogOutputHoldsTheLastMeasurementL53) {
  // §8.10: "If the analog output is disabled, its value remains the same as it was at the last
  // measurement before the output was disabled."
  Rig rig;  // code 25000 over limits 0-50000, 4-20 mA: 12 mA
  rig.run_for(20ms);
  EXPECT_DOUBLE_EQ(rig.fw->analog_value(), 12.0);
  rig.write(0x03, 0x00);
  rig.set_scene_code(40000);
  const auto count = rig.fw->measurements();
  rig.run_for(50ms);
  EXPECT_GT(rig.fw->measurements(), count);  // still measuring
  EXPECT_EQ(rig.fw->current_result().value, 40000);
  EXPECT_DOUBLE_EQ(rig.fw->analog_value(), 12.0);
  // Enabled again, the next measurement updates it: 4 + 16 × 0.8 = 16.8 mA.
  rig.write(0x03, 0x01);
  rig.run_for(10ms);
  EXPECT_DOUBLE_EQ(rig.fw->analog_value(), 16.8);
}

TEST(Ls5Commands, AnalogOutputDisabledSincePowerUpShowsNoResult) {
  // No measurement before it was disabled: §8.2's "state of no result (the minimum value of current
  // or voltage - for example, for a 4-20 mA setting, this is 4 mA)" (L53).
  Rig rig;
  rig.write(0x03, 0x00);
  EXPECT_EQ(rig.exchange("#01FL\r"), "!01FL\r");
  rig.fw->power_cycle(rig.now);
  const auto count = rig.fw->measurements();
  rig.run_for(50ms);
  EXPECT_GT(rig.fw->measurements(), count);
  EXPECT_DOUBLE_EQ(rig.fw->analog_value(), 4.0);
}

TEST(Ls5Commands, PowerOnStateOffKeepsTheLaserOffAfterPowerCycle) {
  Rig rig;
  rig.write(0x02, 0x00);
  EXPECT_EQ(rig.exchange("#01FL\r"), "!01FL\r");
  rig.fw->power_cycle(rig.now);
  EXPECT_FALSE(rig.fw->laser_on());
  const auto count = rig.fw->measurements();
  rig.run_for(100ms);
  EXPECT_EQ(rig.fw->measurements(), count);
}

TEST(Ls5Commands, StreamSendsRecordsAndStopsOnStopCommand) {
  Rig rig;
  rig.out.clear();
  rig.send("#01ST\r");
  rig.run_for(35ms);
  EXPECT_EQ(rig.out, "!25000\r!25000\r!25000\r");
  EXPECT_EQ(rig.exchange("#01SB\r", 50ms), "!01SB\r");
}

TEST(Ls5Commands, StreamStopsOnAnyByte) {
  Rig rig;
  rig.send("#01ST\r");
  rig.run_for(25ms);
  EXPECT_EQ(rig.exchange("x", 50ms), "");
  EXPECT_FALSE(rig.fw->streaming());
}

TEST(Ls5Commands, ThinningSendsEveryNthResult) {
  Rig rig;
  rig.write(0x08, 0x03);
  rig.out.clear();
  rig.send("#01ST\r");
  rig.run_for(95ms);  // 9 measurements
  EXPECT_EQ(rig.out, "!25000\r!25000\r!25000\r");
}

TEST(Ls5Commands, BaudChangeTakesEffectAfterTheEcho) {
  Rig rig;
  rig.out.clear();
  rig.send("#01W0506\r");
  EXPECT_EQ(rig.fw->port_settings(0).baud, 115200U);
  rig.run_for(5ms);
  EXPECT_EQ(rig.out, "!01W0506\r");
  EXPECT_EQ(rig.fw->port_settings(0).baud, 230400U);
  // Every echo byte left at 115200 8N1: 86.8 µs each.
  EXPECT_NEAR(static_cast<double>(rig.bytes.back().done.count()), 9 * 86805.6, 100);
  rig.write(0x04, 0x04);  // 8E2
  EXPECT_EQ(rig.fw->port_settings(0).stop_bits, 2);
  EXPECT_EQ(rig.fw->port_settings(0).parity, rangekit::Parity::even);
}

}  // namespace
}  // namespace rangekit::ls5::emulator::testing
