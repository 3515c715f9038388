// What a unit's input registers say about samples of each family: the reading in mm and µm,
// the status bits, the device error, the targets, and when a value turns stale.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>

#include "modbus/unit_state.hpp"
#include "record/fake_source.hpp"

namespace {

using namespace rangekit;
using namespace rangekit::modbus;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

float float_at(const InputImage& image, std::uint16_t at) {
  return std::bit_cast<float>(u32_of_words(image[at], image[at + 1], WordOrder::abcd));
}
std::int32_t int_at(const InputImage& image, std::uint16_t at) {
  return static_cast<std::int32_t>(u32_of_words(image[at], image[at + 1], WordOrder::abcd));
}
bool bit(const InputImage& image, unsigned which) { return ((image[input::status] >> which) & 1U) != 0; }

UnitState live() {
  UnitState state;
  hub::SensorHealth health;
  health.connected = true;
  health.rate_hz = 10;
  health.records = 0x1'0000'0005;  // a count past 32 bits: its low 32 bits
  health.errors = 2;
  health.lost = 3;
  apply_health(state, true, health);
  return state;
}

TEST(ModbusUnitState, AUlsAveragingReadingInMillimetresAndMicrometres) {
  UnitState state = live();
  const auto now = Clock::now();
  apply_sample(state, rangekit::record::testing::uls_averaging(), now);  // 12.345 m
  const InputImage image = input_registers(state, now + 5ms, WordOrder::abcd);
  EXPECT_FLOAT_EQ(float_at(image, input::reading_mm), 12345.0F);
  EXPECT_EQ(int_at(image, input::reading_um), 12345000);
  EXPECT_TRUE(bit(image, status_bit::connected));
  EXPECT_TRUE(bit(image, status_bit::streaming));
  EXPECT_TRUE(bit(image, status_bit::valid));
  EXPECT_FALSE(bit(image, status_bit::stale));
  EXPECT_FALSE(bit(image, status_bit::no_target));
  EXPECT_EQ(image[input::device_error], 0);
  EXPECT_EQ(u32_of_words(image[input::sequence], image[input::sequence + 1], WordOrder::abcd), 1U);
  EXPECT_EQ(image[input::age_ms], 5);
  EXPECT_EQ(u32_of_words(image[input::records], image[input::records + 1], WordOrder::abcd), 5U);
  EXPECT_EQ(u32_of_words(image[input::errors], image[input::errors + 1], WordOrder::abcd), 2U);
  EXPECT_EQ(u32_of_words(image[input::lost], image[input::lost + 1], WordOrder::abcd), 3U);
  EXPECT_EQ(image[input::target_count], 1);
  // Another sample: the sequence rises by one.
  apply_sample(state, rangekit::record::testing::uls_averaging(), now);
  const InputImage next = input_registers(state, now, WordOrder::cdab);
  EXPECT_EQ(u32_of_words(next[input::sequence], next[input::sequence + 1], WordOrder::cdab), 2U);
  EXPECT_EQ(next[input::reading_um], 0x5EA8);  // 12345000 = 0x00BC5EA8, low word first
  EXPECT_EQ(next[input::reading_um + 1], 0x00BC);
}

TEST(ModbusUnitState, ABinningBurstGivesItsNearestTargetAndEveryTarget) {
  UnitState state = live();
  Sample burst = rangekit::record::testing::uls_binning();
  burst.targets = {{7.1, 13}, {4.572, 42}};
  const auto now = Clock::now();
  apply_sample(state, burst, now);
  const InputImage image = input_registers(state, now, WordOrder::abcd);
  EXPECT_FLOAT_EQ(float_at(image, input::reading_mm), 4572.0F);
  EXPECT_EQ(image[input::target_count], 2);
  EXPECT_FLOAT_EQ(float_at(image, input::first_target_mm), 4572.0F);
  EXPECT_FLOAT_EQ(float_at(image, input::first_target_mm + 2), 7100.0F);
  burst.targets = {};
  apply_sample(state, burst, now);
  const InputImage none = input_registers(state, now, WordOrder::abcd);
  EXPECT_TRUE(std::isnan(float_at(none, input::reading_mm)));
  EXPECT_EQ(int_at(none, input::reading_um), INT32_MIN);
  EXPECT_TRUE(bit(none, status_bit::no_target));
  EXPECT_FALSE(bit(none, status_bit::valid));
  EXPECT_EQ(none[input::target_count], 0);
}

TEST(ModbusUnitState, ADeviceErrorIsItsNumberAndNoValidReading) {
  UnitState state = live();
  const auto now = Clock::now();
  apply_sample(state, rangekit::record::testing::uls_error(), now);  // $ER,4
  const InputImage image = input_registers(state, now, WordOrder::abcd);
  EXPECT_EQ(image[input::device_error], 4);
  EXPECT_FALSE(bit(image, status_bit::valid));
  // LS5 §9.3: 65535 "no signal" is its result code, and no target.
  apply_sample(state, rangekit::record::testing::ls5_result(65535, std::nullopt, ls5::SignalState::lost), now);
  const InputImage lost = input_registers(state, now, WordOrder::abcd);
  EXPECT_EQ(lost[input::device_error], 65535);
  EXPECT_TRUE(bit(lost, status_bit::no_target));
  apply_sample(state, rangekit::record::testing::ls5_result(20000, 10.0, ls5::SignalState::ok), now);
  const InputImage seen = input_registers(state, now, WordOrder::abcd);
  EXPECT_EQ(seen[input::device_error], 0);
  EXPECT_FLOAT_EQ(float_at(seen, input::reading_mm), 10.0F);
  EXPECT_TRUE(bit(seen, status_bit::valid));
}

TEST(ModbusUnitState, LookDownHasNoDistanceAndSaysWhenNothingIsThere) {
  UnitState state = live();
  const auto now = Clock::now();
  Sample edge = rangekit::record::testing::uls_look_down();
  apply_sample(state, edge, now);
  EXPECT_FALSE(bit(input_registers(state, now, WordOrder::abcd), status_bit::no_target));
  edge.set(uls::channel::presence, false);
  apply_sample(state, edge, now);
  const InputImage image = input_registers(state, now, WordOrder::abcd);
  EXPECT_TRUE(bit(image, status_bit::no_target));
  EXPECT_TRUE(std::isnan(float_at(image, input::reading_mm)));
}

TEST(ModbusUnitState, StaleAfterThreePeriodsOrTwoSecondsAndWhenDisconnected) {
  UnitState state = live();  // 10 Hz: 300 ms
  const auto now = Clock::now();
  EXPECT_TRUE(is_stale(state, now));  // nothing heard yet
  apply_sample(state, rangekit::record::testing::uls_averaging(), now);
  EXPECT_FALSE(is_stale(state, now + 300ms));
  EXPECT_TRUE(is_stale(state, now + 301ms));
  state.rate_hz = 1000;  // 3 ms, but never sooner than 100 ms
  EXPECT_FALSE(is_stale(state, now + 100ms));
  EXPECT_TRUE(is_stale(state, now + 101ms));
  state.rate_hz = 0;  // rate not known
  EXPECT_FALSE(is_stale(state, now + 2s));
  EXPECT_TRUE(is_stale(state, now + 2001ms));
  hub::SensorHealth gone;
  gone.connected = false;
  apply_health(state, false, gone);
  const InputImage image = input_registers(state, now, WordOrder::abcd);
  EXPECT_TRUE(bit(image, status_bit::stale));
  EXPECT_FALSE(bit(image, status_bit::connected));
  EXPECT_FLOAT_EQ(float_at(image, input::reading_mm), 12345.0F);  // the last value kept
  EXPECT_EQ(input_registers(state, now + 70s, WordOrder::abcd)[input::age_ms], 65535);
}

}  // namespace
