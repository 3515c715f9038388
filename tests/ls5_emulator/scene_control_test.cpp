// Scene files (TOML) and the firmware's control commands.
#include <fstream>

#include "ls5_emulator/firmware_rig.hpp"

namespace rangekit::ls5::emulator::testing {
namespace {

TEST(Ls5Scene, ParsesTargetPathDustAndDropouts) {
  auto scene = parse_scene(R"(
[target]
path = [[0.0, 20.0], [1.0, 30.0]]
repeat = true
reflectivity = 0.5
noise_mm = 0.01

[dust]
probability = 0.02

[[dropout]]
start_s = 1.0
end_s = 1.5
kind = "dust"
)",
                           "scene.toml");
  ASSERT_TRUE(scene) << scene.error().message;
  EXPECT_TRUE(scene->target_set);
  EXPECT_DOUBLE_EQ(scene->target.position_at(500ms), 25.0);
  EXPECT_DOUBLE_EQ(scene->reflectivity, 0.5);
  EXPECT_DOUBLE_EQ(scene->noise_mm, 0.01);
  EXPECT_DOUBLE_EQ(scene->dust_probability, 0.02);
  ASSERT_EQ(scene->dropouts.size(), 1U);
  EXPECT_EQ(scene->dropouts[0].kind, "dust");
}

TEST(Ls5Scene, ConstantSpeedTarget) {
  auto scene = parse_scene("[target]\nposition_mm = 20.0\nspeed_mm_per_s = 2.0\n", "s.toml");
  ASSERT_TRUE(scene) << scene.error().message;
  EXPECT_DOUBLE_EQ(scene->target.position_at(1500ms), 23.0);
}

TEST(Ls5Scene, ErrorsNameFileLineAndKey) {
  auto bad_value = parse_scene("[target]\nposition_mm = 20.0\nreflectivity = 2.0\n", "scene.toml");
  ASSERT_FALSE(bad_value);
  EXPECT_NE(bad_value.error().message.find("scene.toml:3: reflectivity"), std::string::npos)
      << bad_value.error().message;
  auto unknown = parse_scene("[target]\nposition = 20.0\n", "scene.toml");
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.error().message.find("scene.toml:2: position"), std::string::npos) << unknown.error().message;
  auto syntax = parse_scene("[target\n", "scene.toml");
  ASSERT_FALSE(syntax);
  EXPECT_NE(syntax.error().message.find("scene.toml:1"), std::string::npos) << syntax.error().message;
  auto dropout = parse_scene("[[dropout]]\nstart_s = 2.0\nend_s = 1.0\n", "scene.toml");
  ASSERT_FALSE(dropout);
  EXPECT_NE(dropout.error().message.find("scene.toml:1: dropout"), std::string::npos) << dropout.error().message;
  auto missing = load_scene("/nonexistent/rangekit-scene.toml");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("/nonexistent/rangekit-scene.toml"), std::string::npos);
}

TEST(Ls5Scene, DustDropsSomeMeasurements) {
  FirmwareConfig config = test_config();
  config.scene.dust_probability = 0.5;
  Rig rig(config);
  rig.write(0x09, 0x00);
  rig.write(0x0A, 0x00);  // τ = 0: every lost measurement shows
  int lost = 0;
  for (int i = 0; i < 200; ++i) {
    rig.run_for(10ms);
    if (rig.fw->current_result().value == code_no_signal) ++lost;
  }
  EXPECT_GT(lost, 60);
  EXPECT_LT(lost, 140);
}

TEST(Ls5Scene, NoiseStaysWithinTheTable51Error) {
  FirmwareConfig config = test_config();
  config.scene.noise_mm = 1.0;  // far more than the ±0.075 mm error of a 50 mm range: clamped
  Rig rig(config);
  for (int i = 0; i < 200; ++i) {
    rig.run_for(10ms);
    EXPECT_NEAR(rig.fw->current_result().value, 25000, 75);  // 0.075 mm = 75 codes
  }
}

TEST(Ls5Control, MoveTargetSyncOutputsAndPowerCycle) {
  Rig rig;
  auto moved = rig.fw->control({{"cmd", "move_target"}, {"position_mm", 20.0}}, rig.now);
  EXPECT_EQ(moved["ok"], true);
  rig.run_for(20ms);
  EXPECT_EQ(rig.fw->current_result().value, 10000);
  auto outputs = rig.fw->control({{"cmd", "outputs"}}, rig.now);
  EXPECT_EQ(outputs["result"], 10000);
  EXPECT_EQ(outputs["unit"], "mA");
  EXPECT_EQ(outputs["laser"], true);
  auto synced = rig.fw->control({{"cmd", "sync"}, {"level", "pulse"}}, rig.now);  // latching 01 by default
  EXPECT_EQ(synced["latched"], 10000);
  EXPECT_TRUE(rig.fw->control({{"cmd", "sync"}, {"level", "sideways"}}, rig.now).contains("error"));
  auto scene =
      rig.fw->control({{"cmd", "set_scene"}, {"toml", "[target]\nposition_mm = 40.0\nnoise_mm = 0.0\n"}}, rig.now);
  EXPECT_EQ(scene["ok"], true) << scene.dump();
  rig.run_for(20ms);
  EXPECT_EQ(rig.fw->current_result().value, 30000);
  auto bad_scene = rig.fw->control({{"cmd", "set_scene"}, {"toml", "[target]\nspeed = 1\n"}}, rig.now);
  EXPECT_TRUE(bad_scene.contains("error"));
  auto cycled = rig.fw->control({{"cmd", "power_cycle"}}, rig.now);
  EXPECT_EQ(cycled["phase"], "operating");
  EXPECT_EQ(rig.fw->current_result().value, code_no_measurement_yet);
  auto unknown = rig.fw->control({{"cmd", "warp"}}, rig.now);
  EXPECT_NE(unknown["error"].get<std::string>().find("unknown command 'warp'"), std::string::npos);
}

TEST(Ls5Control, CreateRefusesBadIdentity) {
  FirmwareConfig config = test_config("LS6.1.0");
  EXPECT_FALSE(Firmware::create(config));
  config = test_config();
  config.factory_address = 0;
  EXPECT_FALSE(Firmware::create(config));
  config = test_config();
  config.serial_number = 12345678;  // 7 digits at most
  EXPECT_FALSE(Firmware::create(config));
  EXPECT_TRUE(parse_model("8.1234/40.001"));
  EXPECT_FALSE(parse_model("8.1234-40.001"));
  EXPECT_FALSE(parse_model("8/0"));
  auto ordered = parse_model("LS5-100/200-232-U10-2-12-A");
  ASSERT_TRUE(ordered) << ordered.error().message;
  EXPECT_DOUBLE_EQ(ordered->range_mm, 200);
  EXPECT_FALSE(has_ethernet(*ordered));
  EXPECT_EQ(ordered->analog.unit, "V");
}

TEST(Ls5Control, MissingDiscreteOutputsStayZero) {
  FirmwareConfig config = test_config();
  config.discrete_outputs = 1;
  Rig rig(config);
  rig.write(0x15, 0x22);  // both "enabled", N = 1
  rig.write(0x1A, 0x00);
  rig.write(0x1B, 0x00);
  rig.write(0x1C, 0x00);
  rig.write(0x1D, 0x00);  // output 2's swings 0..0: 25000 is outside, so it would be N = 1
  rig.write(0x16, 0x00);
  rig.write(0x17, 0x00);
  rig.write(0x18, 0x00);
  rig.write(0x19, 0x00);
  rig.run_for(20ms);
  EXPECT_TRUE(rig.fw->output1());
  EXPECT_FALSE(rig.fw->output2());  // not fitted
}

TEST(Ls5Control, Rs232OrderingCodeHasNoEthernetEvenOnLs512) {
  FirmwareConfig config = test_config("LS5.12.0");
  config.ethernet = false;
  int packets = 0;
  config.udp_sink = [&](const UdpDatagram&) {
    ++packets;
    return ok_status();
  };
  Rig rig(config);
  EXPECT_EQ(rig.exchange("#01R70\r"), "");
  rig.run_for(3s);
  EXPECT_EQ(packets, 0);
}

}  // namespace
}  // namespace rangekit::ls5::emulator::testing
