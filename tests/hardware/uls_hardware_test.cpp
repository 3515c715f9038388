// Hardware tier, ULS: a real unit on RANGEKIT_ULS_PORT (see hardware_env.hpp).
// Identifies it, reads every setting of the configuration file, takes a polled
// and a streamed reading, and (with RANGEKIT_HW_WRITE=1) writes a setting and puts
// it back. Each test returns the unit to measuring or idle as it found it.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <variant>

#include "hardware/hardware_env.hpp"
#include "rangekit/uls/driver.hpp"
#include "rangekit/uls/host_config.hpp"

namespace {

using namespace std::chrono_literals;

std::unique_ptr<rangekit::uls::Driver> connect_uls() {
  auto port = hardware_test::open_port("RANGEKIT_ULS_PORT", "RANGEKIT_ULS_BAUD");
  if (!port) return nullptr;
  rangekit::uls::DriverOptions options;
  options.address = hardware_test::env_uls_address("RANGEKIT_ULS_ADDRESS");
  return std::make_unique<rangekit::uls::Driver>(std::move(port), options);
}

// Puts the unit back to measuring or idle, as it was when the test began.
class RestoreMeasuring {
 public:
  explicit RestoreMeasuring(rangekit::uls::Driver& driver) : driver_(driver) {
    auto status = driver_.status();
    EXPECT_TRUE(status) << status.error().describe();
    was_measuring_ = status && status->measuring();
  }
  ~RestoreMeasuring() {
    auto status = driver_.status();
    if (!status) return;
    if (was_measuring_ && !status->measuring()) {
      EXPECT_TRUE(driver_.start_measuring());
    }
    if (!was_measuring_ && status->measuring()) {
      EXPECT_TRUE(driver_.stop_measuring());
    }
  }
  RestoreMeasuring(const RestoreMeasuring&) = delete;
  RestoreMeasuring& operator=(const RestoreMeasuring&) = delete;

 private:
  rangekit::uls::Driver& driver_;
  bool was_measuring_ = false;
};

TEST(UlsHardware, IdentifiesTheUnit) {
  RANGEKIT_REQUIRE_ENV("RANGEKIT_ULS_PORT");
  auto driver = connect_uls();
  ASSERT_TRUE(driver);
  auto info = driver->info();
  ASSERT_TRUE(info) << info.error().describe();
  EXPECT_FALSE(info->version.empty());
  std::printf("ULS: %s, status 0x%02X\n", info->version.c_str(), info->status.value);
}

TEST(UlsHardware, ReadsEverySettingOfTheConfigFile) {
  RANGEKIT_REQUIRE_ENV("RANGEKIT_ULS_PORT");
  auto driver = connect_uls();
  ASSERT_TRUE(driver);
  auto config = rangekit::uls::read_config(*driver);
  ASSERT_TRUE(config) << config.error().describe();
  EXPECT_EQ(config->settings.size(), rangekit::uls::config_commands().size());
  // What `rangekit uls config save` writes must read back as the same values.
  const auto text = rangekit::uls::config_to_toml(*config, "hardware test");
  auto parsed = rangekit::uls::config_from_toml(text, "hardware test");
  ASSERT_TRUE(parsed) << parsed.error().describe();
  EXPECT_TRUE(rangekit::uls::diff_config(*parsed, *config).empty()) << text;
}

TEST(UlsHardware, TakesOnePolledReading) {
  RANGEKIT_REQUIRE_ENV("RANGEKIT_ULS_PORT");
  auto driver = connect_uls();
  ASSERT_TRUE(driver);
  RestoreMeasuring restore(*driver);
  auto reading = driver->measure();
  ASSERT_TRUE(reading) << reading.error().describe();
  EXPECT_EQ(reading->device, "uls");
}

TEST(UlsHardware, StreamsTenReadings) {
  RANGEKIT_REQUIRE_ENV("RANGEKIT_ULS_PORT");
  auto driver = connect_uls();
  ASSERT_TRUE(driver);
  RestoreMeasuring restore(*driver);
  auto started = driver->start_stream();
  ASSERT_TRUE(started) << started.error().describe();
  int samples = 0;
  // PRF/PPM is at least a few Hz for every setting a unit ships with; 30 s is generous.
  const auto give_up = std::chrono::steady_clock::now() + 30s;
  while (samples < 10 && std::chrono::steady_clock::now() < give_up) {
    auto item = (*started)->next(500ms);
    if (!item) continue;
    if (const auto* event = std::get_if<rangekit::StreamEvent>(&*item)) {
      EXPECT_NE(event->kind, rangekit::StreamEventKind::bad_frame) << event->message;
      EXPECT_NE(event->kind, rangekit::StreamEventKind::disconnected) << event->message;
    } else {
      ++samples;
    }
  }
  (*started)->stop(rangekit::uls::AfterStream::keep_measuring);
  EXPECT_EQ(samples, 10);
  EXPECT_EQ((*started)->lost(), 0U);
  EXPECT_EQ(driver->counters().bad_frames, 0U);
}

TEST(UlsHardware, WritesASettingAndPutsItBack) {
  RANGEKIT_REQUIRE_ENV("RANGEKIT_ULS_PORT");
  RANGEKIT_REQUIRE_WRITES();
  auto driver = connect_uls();
  ASSERT_TRUE(driver);
  RestoreMeasuring restore(*driver);
  auto status = driver->status();
  ASSERT_TRUE(status);
  // Most settings answer 31 while measuring (U24); the offset is written idle.
  if (status->measuring()) {
    ASSERT_TRUE(driver->stop_measuring());
  }
  auto offset = driver->offset_m();
  ASSERT_TRUE(offset) << offset.error().describe();
  const double trial = *offset == 0.5 ? 0.25 : 0.5;
  ASSERT_TRUE(driver->set_offset_m(trial));
  auto changed = driver->offset_m();
  ASSERT_TRUE(changed);
  EXPECT_NEAR(*changed, trial, 0.01);
  ASSERT_TRUE(driver->set_offset_m(*offset));
  auto restored = driver->offset_m();
  ASSERT_TRUE(restored);
  EXPECT_NEAR(*restored, *offset, 0.005);
}

}  // namespace
