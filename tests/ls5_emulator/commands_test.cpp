// Every command of table 9.1 against the firmware model, byte for byte.
// Conformance rows held here: L26 (no reply to what the sensor cannot honour), L27 (DF in RAM),
// L28 (serial settings after the echo), L37 (any byte stops the stream), L39 (OF).
#include <unistd.h>

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
  EXPECT_EQ(rig.exchange("#01XX\r"), "");             // not a command
  EXPECT_EQ(rig.exchange("#01R06\r"), "!01R0664\r");  // still answering
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
