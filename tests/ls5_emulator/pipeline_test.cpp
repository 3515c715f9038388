// The measurement pipeline of figure 8.7 and the outputs, against hand-computed values.
// Conformance rows held here: L29 and L54 (standby), L30 and L89 (derivative), L31 and L88 (τ), L32 (filters),
// L33 (§8.13), L34 (exposure and priority), L35 (stream pacing), L36 (UDP), L38 (ROM-writing latching),
// L82 and L93 (UDP source port and destination), L90 and L91 (analog output at equal limits and without signal).
#include <unistd.h>

#include "ls5_emulator/firmware_rig.hpp"

namespace rangekit::ls5::emulator::testing {
namespace {

// Measures one code per period (10 ms) and returns the results the firmware reports.
std::vector<std::uint16_t> feed(Rig& rig, std::initializer_list<double> codes) {
  std::vector<std::uint16_t> results;
  for (const double code : codes) {
    rig.set_scene_code(code);
    const auto before = rig.fw->measurements();
    rig.run_for(10ms);
    EXPECT_EQ(rig.fw->measurements(), before + 1);
    results.push_back(rig.fw->current_result().value);
  }
  return results;
}

TEST(Ls5Pipeline, MovingAverageOfKPoints) {
  Rig rig;
  rig.run_for(5ms);  // measurements fall on 10, 20, ... ms: sit between them
  rig.write(0x0C, 0x03);
  EXPECT_EQ(feed(rig, {1000, 2000, 6000, 6000}), (std::vector<std::uint16_t>{1000, 1500, 3000, 4667}));
}

TEST(Ls5Pipeline, MedianOfMPoints) {
  Rig rig;
  rig.run_for(5ms);
  rig.write(0x0D, 0x03);
  rig.write(0x0B, 0x01);
  EXPECT_EQ(feed(rig, {1000, 9000, 2000, 3000, 40000}), (std::vector<std::uint16_t>{1000, 9000, 2000, 3000, 3000}));
}

TEST(Ls5Pipeline, DerivativeIsDifferencePlus25000) {
  Rig rig;
  rig.run_for(5ms);
  rig.write(0x0E, 0x01);
  EXPECT_EQ(feed(rig, {1000, 1500, 1200}), (std::vector<std::uint16_t>{25000, 25500, 24700}));
}

TEST(Ls5Pipeline, OutOfRangeIsNoSignal) {
  Rig rig;
  rig.run_for(5ms);
  rig.fw->set_scene(fixed_scene(5));  // before the lower boundary (10 mm)
  rig.write(0x0A, 0x00);
  rig.write(0x09, 0x00);  // τ = 0
  rig.run_for(10ms);
  EXPECT_EQ(rig.fw->current_result().value, code_no_signal);
}

TEST(Ls5Pipeline, SignalAbsenceHoldsTheLastResultForTau) {
  Rig rig;
  rig.write(0x06, 0x0A);  // t = 1 ms; τ stays at its default 10 ms
  Scene scene = fixed_scene(position_for_code(12345));
  scene.dropouts.push_back(Dropout{0.1, 0.2, "shading"});
  rig.fw->set_scene(scene);
  rig.run_to(Nanos(108'500'000));  // last valid result at 99 ms (measurements on whole ms + write offsets)
  EXPECT_EQ(rig.fw->current_result().value, 12345);
  rig.run_to(Nanos(115'000'000));
  EXPECT_EQ(rig.fw->current_result().value, code_no_signal);
  rig.run_to(Nanos(205'000'000));
  EXPECT_EQ(rig.fw->current_result().value, 12345);
}

TEST(Ls5Pipeline, DefaultTauBridgesOneLostMeasurementAtTheDefaultPeriodL88) {
  // §8.6: "Acceptable time of signal absense, τ – the time during which, in the absence of a
  // signal, the result remains equal to the last measured value in the range." Table 9.2: τ
  // "for τ = 10 ms parameter is 000A", default 0A 00; the period's default 64 00 "(corresponds
  // 10 ms)". A lost measurement 10 ms after the last result is within τ, one 20 ms after is not.
  Rig rig;  // measurements at 10, 20, ... ms, code 25000
  Scene scene = fixed_scene(position_for_code(25000));
  scene.dropouts = {{0.045, 0.055, "dust"}, {0.075, 0.095, "shading"}};  // loses 50 ms; 80 and 90 ms
  rig.fw->set_scene(scene);
  std::vector<std::uint16_t> results;
  for (int i = 0; i < 10; ++i) {
    rig.run_for(10ms);
    results.push_back(rig.fw->current_result().value);
  }
  EXPECT_EQ(results, (std::vector<std::uint16_t>{25000, 25000, 25000, 25000, 25000, 25000, 25000, 25000, code_no_signal,
                                                 25000}));
}

TEST(Ls5Pipeline, ALossTauDoesNotBridgeRestartsTheDerivativeAndTheFilterL89) {
  // §8.8: "A derivative is the difference between the current and previous results."; after a
  // result of 65535 ("no signal", §8.9) the next result has no previous result to differ from.
  Rig rig;
  rig.run_for(5ms);
  rig.write(0x0E, 0x01);
  rig.write(0x09, 0x00);  // τ = 0: every lost measurement is a loss
  EXPECT_EQ(feed(rig, {1000, 1200}), (std::vector<std::uint16_t>{25000, 25200}));
  rig.fw->set_scene(fixed_scene(5));  // before the lower boundary: no signal
  rig.run_for(10ms);
  EXPECT_EQ(rig.fw->current_result().value, code_no_signal);
  EXPECT_EQ(feed(rig, {1500, 1600}), (std::vector<std::uint16_t>{25000, 25100}));  // not 25300 first

  // A loss τ bridges (default 10 ms) is none: the next difference spans it, 2000 − 1700.
  Rig bridged;
  bridged.run_for(5ms);
  bridged.write(0x0E, 0x01);
  EXPECT_EQ(feed(bridged, {1500, 1700}), (std::vector<std::uint16_t>{25000, 25200}));
  bridged.fw->set_scene(fixed_scene(5));
  bridged.run_for(10ms);
  EXPECT_EQ(bridged.fw->current_result().value, 25200);  // held
  EXPECT_EQ(feed(bridged, {2000}), (std::vector<std::uint16_t>{25300}));

  // The moving average (k = 3) starts again from the new results too (L32).
  Rig average;
  average.run_for(5ms);
  average.write(0x0C, 0x03);
  average.write(0x09, 0x00);
  EXPECT_EQ(feed(average, {1000, 2000}), (std::vector<std::uint16_t>{1000, 1500}));
  average.fw->set_scene(fixed_scene(5));
  average.run_for(10ms);
  EXPECT_EQ(feed(average, {4000, 5000}), (std::vector<std::uint16_t>{4000, 4500}));
}

TEST(Ls5Pipeline, EqualAnalogLimitsGiveAMinL90) {
  // §8.10 formula 8.3: "A = A_min, if ... K_v = K_n" (the linear case divides by K_v − K_n).
  Rig rig;
  rig.run_for(5ms);
  rig.write(0x11, 0x20);
  rig.write(0x12, 0x4E);  // K_n = 20000 (0x4E20)
  rig.write(0x13, 0x20);
  rig.write(0x14, 0x4E);  // K_v = 20000
  for (const double code : {10000.0, 20000.0, 40000.0}) {
    feed(rig, {code});
    EXPECT_DOUBLE_EQ(rig.fw->analog_value(), 4.0) << code;  // 4-20 mA: A_min
  }
  rig.write(0x09, 0x00);  // τ = 0
  rig.fw->set_scene(fixed_scene(5));
  rig.run_for(10ms);
  EXPECT_DOUBLE_EQ(rig.fw->analog_value(), 4.0);  // no signal after A_min: the lower extreme
}

TEST(Ls5Pipeline, NoSignalDrivesTheAnalogOutputToTheExtremeItsLastValueWasNearerL91) {
  // §8.10: "To indicate the status «No signal» on the analog output, the setting to the extreme
  // position is applied depending on the last measured value." 4-20 mA, τ = 0.
  Rig rig;
  rig.run_for(5ms);
  rig.write(0x09, 0x00);
  rig.write(0x11, 0x10);
  rig.write(0x12, 0x27);  // K_n = 10000 (0x2710)
  rig.write(0x13, 0x30);
  rig.write(0x14, 0x75);  // K_v = 30000 (0x7530)
  const auto lose = [&rig] {
    rig.fw->set_scene(fixed_scene(5));  // before the lower boundary
    rig.run_for(10ms);
    EXPECT_EQ(rig.fw->current_result().value, code_no_signal);
  };
  // 22000 gave 4 + 16 × 12000 / 20000 = 13.6 mA, above mid-scale (12 mA): 20 mA, although
  // 22000 is below the middle of the measuring range (25000).
  feed(rig, {22000});
  EXPECT_NEAR(rig.fw->analog_value(), 13.6, 1e-9);
  lose();
  EXPECT_DOUBLE_EQ(rig.fw->analog_value(), 20.0);
  feed(rig, {12000});  // 4 + 16 × 2000 / 20000 = 5.6 mA: 4 mA
  lose();
  EXPECT_DOUBLE_EQ(rig.fw->analog_value(), 4.0);
  // Inverted (K_v = 10000 < K_n = 30000): 12000 gives 4 + 16 × 0.9 = 18.4 mA, so 20 mA.
  rig.write(0x11, 0x30);
  rig.write(0x12, 0x75);
  rig.write(0x13, 0x10);
  rig.write(0x14, 0x27);
  feed(rig, {12000});
  EXPECT_NEAR(rig.fw->analog_value(), 18.4, 1e-9);
  lose();
  EXPECT_DOUBLE_EQ(rig.fw->analog_value(), 20.0);
}

TEST(Ls5Pipeline, SensitivityPriorityLowersTheRateOnWeakTargets) {
  Rig rig;
  rig.write(0x06, 0x0A);                      // t = 1 ms
  rig.fw->set_scene(fixed_scene(35, 0.005));  // needs 4 ms of exposure (max 9.4 ms by default)
  auto before = rig.fw->measurements();
  rig.run_for(1s);
  EXPECT_NEAR(static_cast<double>(rig.fw->measurements() - before), 250, 1);
  EXPECT_EQ(rig.fw->current_result().value, 25000);
  rig.write(0x22, 0x00);  // frequency priority: the rate holds, the weak target is lost
  before = rig.fw->measurements();
  rig.run_for(1s);
  EXPECT_NEAR(static_cast<double>(rig.fw->measurements() - before), 1000, 2);
  EXPECT_EQ(rig.fw->current_result().value, code_no_signal);
}

TEST(Ls5Pipeline, Table93AnalogAndDiscreteExample) {
  Rig rig;
  for (const char* command :
       {"#01W1512\r", "#01W1620\r", "#01W174E\r", "#01W1840\r", "#01W199C\r", "#01W1A10\r", "#01W1B27\r", "#01W1C30\r",
        "#01W1D75\r", "#01W0301\r", "#01W1100\r", "#01W1200\r", "#01W1350\r", "#01W14C3\r"}) {
    std::string echo = command;
    echo[0] = '!';
    EXPECT_EQ(rig.exchange(command), echo);
  }
  struct Point {
    double code;
    bool oc1;
    bool oc2;
    double milliamps;
  };
  // OC1: N = 0, swings 20000/40000; OC2: N = 1, swings 10000/30000; 4-20 mA over 0-50000.
  for (const Point& p :
       {Point{5000, false, true, 5.6}, Point{15000, false, false, 8.8}, Point{25000, true, false, 12.0},
        Point{35000, true, true, 15.2}, Point{45000, false, true, 18.4}}) {
    rig.set_scene_code(p.code);
    rig.run_for(10ms);
    EXPECT_EQ(rig.fw->output1(), p.oc1) << p.code;
    EXPECT_EQ(rig.fw->output2(), p.oc2) << p.code;
    EXPECT_NEAR(rig.fw->analog_value(), p.milliamps, 1e-9) << p.code;
  }
  // No signal: the extreme nearer the last output (18.4 mA is above mid-scale: 20 mA, L8).
  rig.write(0x09, 0x00);
  rig.write(0x0A, 0x00);
  rig.fw->set_scene(fixed_scene(200));
  rig.run_for(10ms);
  EXPECT_DOUBLE_EQ(rig.fw->analog_value(), 20.0);
}

TEST(Ls5Pipeline, WeldingExampleOfSection814WithTheSyncInput) {
  FirmwareConfig config = test_config("LS5.9.0");
  config.lower_boundary_mm = 0;
  config.range_mm = 100;
  config.scene = fixed_scene(50);  // code 25000
  config.state_dir = temp_dir("welding");
  Rig rig(config);
  rig.write(0x25, 0x10);
  rig.write(0x26, 0x27);  // D = 10000
  rig.write(0x1F, 0x09);
  rig.write(0x15, 0x21);
  rig.run_for(20ms);
  rig.fw->set_sync_input(true, rig.now);  // the button
  rig.fw->set_sync_input(false, rig.now + 1ms);
  EXPECT_EQ(rig.exchange("#01FR\r"), "!01FR25000\r");
  EXPECT_EQ(rig.exchange("#01R16\r"), "!01R1620\r");
  EXPECT_EQ(rig.exchange("#01R17\r"), "!01R174E\r");
  EXPECT_EQ(rig.exchange("#01R1C\r"), "!01R1C30\r");
  EXPECT_EQ(rig.exchange("#01R1D\r"), "!01R1D75\r");
  EXPECT_EQ(rig.fw->rom(0x17), 0x4E);
  EXPECT_EQ(rig.fw->rom(0x1D), 0x75);
  // Only the recalculated limits went to ROM: latching and outputs are still the defaults there.
  EXPECT_EQ(rig.fw->rom(0x1F), default_byte(*find_parameter(0x1F), 157));
  EXPECT_EQ(rig.fw->rom(0x15), default_byte(*find_parameter(0x15), 157));
  Rig restarted(config);
  EXPECT_EQ(restarted.exchange("#01R17\r"), "!01R174E\r");
  EXPECT_EQ(restarted.exchange("#01R1D\r"), "!01R1D75\r");
  std::filesystem::remove_all(config.state_dir);
}

TEST(Ls5Pipeline, SyncTriggeringSkipsEdgesFasterThanThePeriod) {
  Rig rig;
  rig.write(0x1F, 0x00);  // no latching: the sync input only triggers
  rig.write(0x1E, 0x01);
  const auto before = rig.fw->measurements();
  rig.run_for(50ms);
  EXPECT_EQ(rig.fw->measurements(), before);  // no timer
  for (const auto at : {0ms, 5ms, 12ms, 30ms}) {
    rig.run_to(Nanos(100ms) + at);
    rig.fw->set_sync_input(true, rig.now);
    rig.fw->set_sync_input(false, rig.now);
  }
  EXPECT_EQ(rig.fw->measurements(), before + 3);  // the edge at +5 ms came too soon
}

TEST(Ls5Pipeline, AmbiguousCaseSyncLatchingAndStreamGivesNoStreamOutput) {
  Rig rig;
  rig.write(0x1E, 0x01);
  rig.write(0x1F, 0x01);
  rig.out.clear();
  rig.send("#01ST\r");
  rig.run_for(20ms);
  rig.set_scene_code(7000);
  rig.fw->set_sync_input(true, rig.now);
  rig.fw->set_sync_input(false, rig.now);
  rig.run_for(20ms);
  EXPECT_EQ(rig.out, "");
  EXPECT_TRUE(rig.fw->streaming());
  EXPECT_EQ(rig.exchange("#01FR\r"), "!01FR07000\r");
  EXPECT_EQ(rig.exchange("#01LR\r"), "!01LR07000\r");
}

TEST(Ls5Pipeline, TimerTriggeringWithLatchingStillStreams) {
  Rig rig;
  rig.write(0x1F, 0x01);
  rig.out.clear();
  rig.send("#01ST\r");
  rig.run_for(15ms);
  rig.set_scene_code(7000);
  rig.fw->set_sync_input(true, rig.now);  // measurement + latch, timer restarts
  rig.run_for(15ms);
  EXPECT_EQ(rig.out, "!25000\r!07000\r");
  EXPECT_EQ(rig.fw->current_result().value, 7000);
}

TEST(Ls5Pipeline, StreamRateIsOneOverNTimesTOver60Seconds) {
  Rig rig;
  rig.write(0x06, 0x0A);
  rig.write(0x07, 0x00);  // t = 1 ms
  rig.write(0x08, 0x02);  // n = 2: T = 2 ms
  rig.send("#01ST\r");
  const Nanos start = rig.now;
  rig.out.clear();
  rig.run_for(60s);
  const double records = static_cast<double>(rig.out.size()) / 7.0;
  const double rate = records / (static_cast<double>((rig.now - start).count()) / 1e9);
  EXPECT_NEAR(rate, 500.0, 500.0 * 1e-4);
  EXPECT_EQ(rig.fw->records_skipped(), 0U);
}

TEST(Ls5Pipeline, OneKilohertzNeeds115200) {
  Rig rig;
  rig.write(0x06, 0x0A);
  rig.write(0x07, 0x00);  // t = 1 ms, n = 1
  rig.send("#01ST\r");
  rig.run_for(10s);
  EXPECT_EQ(rig.fw->records_skipped(), 0U);
  EXPECT_NEAR(static_cast<double>(rig.fw->records_sent()), 10000, 2);

  Rig slow;
  slow.write(0x06, 0x0A);
  slow.write(0x07, 0x00);
  slow.write(0x05, 0x04);  // 57600: a record takes 1.215 ms (§8.4)
  slow.send("#01ST\r");
  slow.run_for(10s);
  EXPECT_NEAR(static_cast<double>(slow.fw->records_sent()), 5000, 2);
  EXPECT_NEAR(static_cast<double>(slow.fw->records_skipped()), 5000, 2);
}

TEST(Ls5Pipeline, ParityAndStopBitsCountInThePacing) {
  Rig rig;
  rig.write(0x06, 0x0A);
  rig.write(0x07, 0x00);
  rig.write(0x04, 0x04);  // 8E2: 12 bits, a record takes 0.73 ms at 115200 -- still fits 1 kHz
  rig.send("#01ST\r");
  rig.run_for(1s);
  EXPECT_EQ(rig.fw->records_skipped(), 0U);
  EXPECT_TRUE(rig.exchange("#01SB\r").ends_with("!01SB\r"));
  rig.write(0x05, 0x04);  // 57600 8E2: 1.46 ms per record
  rig.send("#01ST\r");
  rig.run_for(1s);
  EXPECT_GT(rig.fw->records_skipped(), 400U);
}

TEST(Ls5Pipeline, StandbyAfterPowerUpWhenStoredBaudIsAbove115200) {
  Rig rig;
  rig.write(0x05, 0x06);  // 230400 (takes effect after the echo)
  rig.send("#01FL\r");
  rig.run_for(5ms);
  const Nanos up = rig.now;
  rig.fw->power_cycle(up);
  EXPECT_EQ(rig.fw->phase_name(), "initializing");
  EXPECT_TRUE(rig.fw->laser_on());                // lights up at once (§8.2)
  EXPECT_EQ(rig.exchange("#01ID\r", 100ms), "");  // deaf for 4 s
  rig.run_to(up + 4s + 1ms);
  EXPECT_EQ(rig.fw->phase_name(), "standby");
  EXPECT_EQ(rig.fw->port_settings(0).baud, 19200U);
  EXPECT_EQ(rig.exchange("#01R05\r"), "!01R0506\r");
  EXPECT_FALSE(rig.fw->laser_on());
  const auto count = rig.fw->measurements();
  rig.run_to(up + 9s - 1ms);
  EXPECT_EQ(rig.fw->port_settings(0).baud, 19200U);
  rig.run_to(up + 9s + 1ms);
  EXPECT_EQ(rig.fw->phase_name(), "operating");
  EXPECT_TRUE(rig.fw->laser_on());
  EXPECT_EQ(rig.fw->port_settings(0).baud, 230400U);
  rig.run_to(up + 9s + 499ms);
  EXPECT_EQ(rig.fw->measurements(), count);
  rig.run_to(up + 9s + 501ms);
  EXPECT_EQ(rig.fw->measurements(), count + 1);
}

TEST(Ls5Pipeline, StandbyLetsTheHostLowerTheBaud) {
  // §8.2: "the sensor waits for 5 seconds for any commands to arrive (you can change the parameters
  // "Baud rate" and "Byte format")"; then it "sets up according to the saved parameters" (L54).
  Rig rig;
  rig.write(0x05, 0x06);
  rig.send("#01FL\r");
  rig.run_for(5ms);
  const Nanos up = rig.now;
  rig.fw->power_cycle(up);
  rig.run_to(up + 4s + 1ms);
  EXPECT_EQ(rig.exchange("#01W0505\r"), "!01W0505\r");
  EXPECT_EQ(rig.exchange("#01FL\r"), "!01FL\r");
  EXPECT_EQ(rig.fw->port_settings(0).baud, 19200U);  // still standby
  rig.run_to(up + 9s + 1ms);
  EXPECT_EQ(rig.fw->port_settings(0).baud, 115200U);
  rig.fw->power_cycle(rig.now);  // 115200 stored: no standby any more
  EXPECT_EQ(rig.fw->phase_name(), "operating");
}

TEST(Ls5Pipeline, StandbyEndsWithTheSavedParametersL54) {
  // §8.2: "the emitter lights up and the sensor sets up according to the saved parameters".
  // A baud written in standby without FL is in RAM only: the sensor comes up at the saved baud.
  Rig rig;
  rig.write(0x05, 0x06);  // 230400
  rig.send("#01FL\r");
  rig.run_for(5ms);
  const Nanos up = rig.now;
  rig.fw->power_cycle(up);
  rig.run_to(up + 4s + 1ms);
  EXPECT_EQ(rig.exchange("#01W0505\r"), "!01W0505\r");  // 115200, RAM only
  EXPECT_EQ(rig.exchange("#01W0C04\r"), "!01W0C04\r");  // averaging points, RAM only
  rig.run_to(up + 9s + 1ms);
  EXPECT_EQ(rig.fw->phase_name(), "operating");
  EXPECT_EQ(rig.fw->port_settings(0).baud, 230400U);
  EXPECT_EQ(rig.exchange("#01R05\r"), "!01R0506\r");  // RAM agrees with the line
  EXPECT_EQ(rig.exchange("#01R0C\r"), "!01R0C01\r");
}

TEST(Ls5Pipeline, UdpPacketEvery168ResultsAtTheOutputPeriod) {
  std::vector<std::array<std::uint8_t, udp_packet_size>> packets;
  FirmwareConfig config = test_config("LS5.12.3");
  config.udp_sink = [&](const UdpDatagram& datagram) {
    packets.push_back(datagram.bytes);
    return ok_status();
  };
  Rig rig(config);
  rig.write(0x06, 0x0A);
  rig.write(0x07, 0x00);  // t = 1 ms
  rig.run_for(1s);
  ASSERT_GE(packets.size(), 5U);
  for (std::size_t i = 0; i < packets.size(); ++i) {
    auto packet = decode_udp_packet(Bytes(packets[i].data(), packets[i].size()));
    ASSERT_TRUE(packet) << packet.error().message;
    EXPECT_EQ(packet->counter, i);
    EXPECT_EQ(packet->serial_number, 157);
    EXPECT_EQ(packet->lower_boundary_mm, 10);
    EXPECT_EQ(packet->range_mm, 50);
    const auto& last = packet->records.back();
    EXPECT_TRUE(last.measured());
    EXPECT_TRUE(last.in_range());
    EXPECT_EQ(last.code, 0x2000);  // code 25000 = half scale
  }
  EXPECT_NEAR(static_cast<double>(packets.size()), 1000.0 / 168, 1);
  rig.write(0x70, 0x00);
  const auto count = packets.size();
  rig.run_for(1s);
  EXPECT_EQ(packets.size(), count);
}

TEST(Ls5Pipeline, UdpPacketsLeaveFromTheSourcePortOfTheParametersL82) {
  // §10 default settings: "Source port number (sensor) 5000"; table 9.2 "Source port number",
  // high byte 6E = 13, low byte 6F = 88, "(5000)".
  std::vector<std::uint16_t> ports;
  Status answer = ok_status();
  FirmwareConfig config = test_config("LS5.12.0");
  config.udp_sink = [&](const UdpDatagram& datagram) {
    ports.push_back(datagram.source_port);
    return answer;
  };
  Rig rig(config);
  rig.write(0x06, 0x0A);  // t = 1 ms: a packet every 168 ms
  rig.run_for(200ms);
  ASSERT_EQ(ports, (std::vector<std::uint16_t>{5000}));
  // "#01W6F89": 0x1389 = 5001, and the next packet follows it.
  rig.write(0x6F, 0x89);
  rig.run_for(170ms);
  EXPECT_EQ(ports.back(), 5001);
  EXPECT_EQ(rig.fw->udp_source_port(), 5001);
  // A port the host cannot bind: the packet is counted unsent, the error kept, and measuring goes on.
  answer = make_error(Errc::io, "UDP source port 5001 (parameters 6E/6F) cannot be used: in use");
  const auto measured = rig.fw->measurements();
  rig.run_for(170ms);
  EXPECT_EQ(rig.fw->udp_unsent(), 1U);
  EXPECT_EQ(rig.fw->control({{"cmd", "outputs"}}, rig.now)["udp_error"], answer.error().message);
  EXPECT_GT(rig.fw->measurements(), measured + 160);
  EXPECT_EQ(rig.exchange("#01R6F\r"), "!01R6F89\r");
  answer = ok_status();
  rig.run_for(170ms);
  EXPECT_TRUE(rig.fw->control({{"cmd", "outputs"}}, rig.now)["udp_error"].is_null());
  // DF brings back 5000 for the next packet, as writing 13 88 would.
  EXPECT_EQ(rig.exchange("#01DF\r"), "!01DF\r");
  rig.write(0x06, 0x0A);
  rig.run_for(170ms);
  EXPECT_EQ(ports.back(), 5000);
}

TEST(Ls5Pipeline, UdpPacketsGoWhereTheDestinationParametersSayL93) {
  // Table 9.2: "Destination IP address" 5C-5F, "Destination port number" 6C (high byte), 6D (low
  // byte); §10's defaults "Destination IP address 255.255.255.255", "Destination port number 603".
  std::vector<UdpDatagram> sent;
  FirmwareConfig config = test_config("LS5.12.0");
  config.udp_destination = UdpDestination{0x7F000001, 6030};  // --udp 127.0.0.1:6030, as delivered
  config.udp_sink = [&](const UdpDatagram& datagram) {
    sent.push_back(datagram);
    return ok_status();
  };
  Rig rig(config);
  EXPECT_EQ(rig.exchange("#01R5C\r"), "!01R5C7F\r");
  EXPECT_EQ(rig.exchange("#01R5F\r"), "!01R5F01\r");
  EXPECT_EQ(rig.exchange("#01R6C\r"), "!01R6C17\r");  // 6030 = 0x178E
  EXPECT_EQ(rig.exchange("#01R6D\r"), "!01R6D8E\r");
  rig.write(0x06, 0x0A);  // t = 1 ms: a packet every 168 ms
  rig.run_for(170ms);
  ASSERT_FALSE(sent.empty());
  EXPECT_EQ(sent.back().destination_ip, 0x7F000001U);
  EXPECT_EQ(sent.back().destination_port, 6030);
  // 127.0.0.2:7000 (0x1B58) from the next packet on.
  rig.write(0x5F, 0x02);
  rig.write(0x6C, 0x1B);
  rig.write(0x6D, 0x58);
  rig.run_for(170ms);
  EXPECT_EQ(sent.back().destination_ip, 0x7F000002U);
  EXPECT_EQ(sent.back().destination_port, 7000);
  // DF: table 9.2's FF FF FF FF and 02 5B (603), at once; FL keeps them, power-up as delivered without it.
  EXPECT_EQ(rig.exchange("#01DF\r"), "!01DF\r");
  rig.write(0x06, 0x0A);
  rig.run_for(170ms);
  EXPECT_EQ(sent.back().destination_ip, 0xFFFFFFFFU);
  EXPECT_EQ(sent.back().destination_port, 603);
  rig.fw->power_cycle(rig.now);
  EXPECT_EQ(rig.exchange("#01R6D\r"), "!01R6D8E\r");
}

TEST(Ls5Pipeline, NoUdpOnSerialOnlyModels) {
  int packets = 0;
  FirmwareConfig config = test_config("LS5.9.0");
  config.udp_sink = [&](const UdpDatagram&) {
    ++packets;
    return ok_status();
  };
  Rig rig(config);
  rig.write(0x06, 0x0A);
  rig.write(0x07, 0x00);
  rig.run_for(1s);
  EXPECT_EQ(packets, 0);
}

}  // namespace
}  // namespace rangekit::ls5::emulator::testing
