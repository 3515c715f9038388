// Hardware tier, LS5: a real sensor on RANGEKIT_LS5_PORT, and its Ethernet stream
// on RANGEKIT_LS5_UDP (see hardware_env.hpp). Identifies it, reads every setting,
// takes a last and a latched result, streams, and (with RANGEKIT_HW_WRITE=1) writes
// a setting in RAM and puts it back; nothing is stored to flash.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <variant>

#include "hardware/hardware_env.hpp"
#include "rangekit/core/udp.hpp"
#include "rangekit/ls5/driver.hpp"
#include "rangekit/ls5/host_config.hpp"
#include "rangekit/ls5/udp_receiver.hpp"

namespace {

using namespace std::chrono_literals;
using hardware_test::env;

std::unique_ptr<rangekit::ls5::Driver> connect_ls5() {
  auto port = hardware_test::open_port("RANGEKIT_LS5_PORT", "RANGEKIT_LS5_BAUD");
  if (!port) return nullptr;
  rangekit::ls5::DriverOptions options;
  options.address = hardware_test::env_ls5_address("RANGEKIT_LS5_ADDRESS");
  return std::make_unique<rangekit::ls5::Driver>(std::move(port), options);
}

// Counts samples from a source until `wanted` or the deadline; fails on bad frames.
int collect(rangekit::SampleSource& source, int wanted, std::chrono::seconds within) {
  int samples = 0;
  const auto give_up = std::chrono::steady_clock::now() + within;
  while (samples < wanted && std::chrono::steady_clock::now() < give_up) {
    auto item = source.next(500ms);
    if (!item) continue;
    if (const auto* event = std::get_if<rangekit::StreamEvent>(&*item)) {
      EXPECT_NE(event->kind, rangekit::StreamEventKind::bad_frame) << event->message;
      EXPECT_NE(event->kind, rangekit::StreamEventKind::disconnected) << event->message;
    } else {
      EXPECT_EQ(std::get<rangekit::Sample>(*item).device, "ls5");
      ++samples;
    }
  }
  return samples;
}

TEST(Ls5Hardware, IdentifiesTheSensor) {
  RANGEKIT_REQUIRE_ENV("RANGEKIT_LS5_PORT");
  auto driver = connect_ls5();
  ASSERT_TRUE(driver);
  auto info = driver->info();
  ASSERT_TRUE(info) << info.error().describe();
  EXPECT_GT(info->identification.range_mm, 0.0);
  std::printf("LS5 at address %u: range %.3f mm, serial %u, ethernet %s\n", info->address,
              info->identification.range_mm, static_cast<unsigned>(info->identification.serial_number),
              info->ethernet ? "yes" : "no");
}

TEST(Ls5Hardware, ReadsEverySetting) {
  RANGEKIT_REQUIRE_ENV("RANGEKIT_LS5_PORT");
  auto driver = connect_ls5();
  ASSERT_TRUE(driver);
  auto config = rangekit::ls5::read_device_config(*driver);
  ASSERT_TRUE(config) << config.error().describe();
  EXPECT_FALSE(config->entries.empty());
  // `rangekit ls5 config diff` of what was just saved finds no difference.
  auto parsed = rangekit::ls5::parse_config_toml(rangekit::ls5::config_to_toml(*config), "hardware test");
  ASSERT_TRUE(parsed) << parsed.error().describe();
  auto differences = rangekit::ls5::diff_config(*driver, *parsed);
  ASSERT_TRUE(differences) << differences.error().describe();
  EXPECT_TRUE(differences->empty());
}

TEST(Ls5Hardware, ReadsTheLastAndALatchedResult) {
  RANGEKIT_REQUIRE_ENV("RANGEKIT_LS5_PORT");
  auto driver = connect_ls5();
  ASSERT_TRUE(driver);
  auto last = driver->read_last();
  ASSERT_TRUE(last) << last.error().describe();
  ASSERT_TRUE(driver->latch());
  auto latched = driver->read_latched();
  ASSERT_TRUE(latched) << latched.error().describe();
}

TEST(Ls5Hardware, StreamsAHundredRecords) {
  RANGEKIT_REQUIRE_ENV("RANGEKIT_LS5_PORT");
  auto driver = connect_ls5();
  ASSERT_TRUE(driver);
  auto stream = driver->start_stream({});
  ASSERT_TRUE(stream) << stream.error().describe();
  // Factory settings stream hundreds of records per second; 30 s covers long
  // periods with thinning too (the stream uses the sensor's own settings).
  const int samples = collect(**stream, 100, 30s);
  (*stream)->stop();
  EXPECT_EQ(samples, 100);
  EXPECT_EQ((*stream)->lost(), 0U);
  EXPECT_EQ(driver->rejected_frames(), 0U);
}

TEST(Ls5Hardware, ReceivesTheEthernetStream) {
  RANGEKIT_REQUIRE_ENV("RANGEKIT_LS5_UDP");
  auto local = rangekit::parse_endpoint(*env("RANGEKIT_LS5_UDP"));
  ASSERT_TRUE(local) << local.error().describe();
  auto receiver = rangekit::ls5::UdpReceiver::start(*local);
  ASSERT_TRUE(receiver) << receiver.error().describe();
  // 168 records per packet (§10.1): 336 is two whole packets.
  EXPECT_EQ(collect(**receiver, 336, 30s), 336);
  (*receiver)->stop();
  EXPECT_EQ((*receiver)->counters().bad_packets, 0U);
}

TEST(Ls5Hardware, WritesASettingInRamAndPutsItBack) {
  RANGEKIT_REQUIRE_ENV("RANGEKIT_LS5_PORT");
  RANGEKIT_REQUIRE_WRITES();
  auto driver = connect_ls5();
  ASSERT_TRUE(driver);
  auto before = driver->get("thinning");
  ASSERT_TRUE(before) << before.error().describe();
  const std::string trial = before->text == "3" ? "5" : "3";
  ASSERT_TRUE(driver->set("thinning", trial));
  auto changed = driver->get("thinning");
  ASSERT_TRUE(changed);
  EXPECT_EQ(changed->text, trial);
  ASSERT_TRUE(driver->set("thinning", before->text));
  auto restored = driver->get("thinning");
  ASSERT_TRUE(restored);
  EXPECT_EQ(restored->text, before->text);
}

}  // namespace
