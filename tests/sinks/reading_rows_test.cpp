// Which hub items become spool rows: a sample's one reading with its family, unit and the
// sensor's next seq; never a sample without a reading or an event; at most max_rate_hz.
#include "sinks/reading_rows.hpp"

#include <gtest/gtest.h>

#include "ls5_driver/cli_process.hpp"
#include "rangekit/core/family.hpp"
#include "rangekit/ls5/family.hpp"

namespace {

using namespace rangekit;
using namespace std::chrono_literals;

hub::HubItem ls5_item(const std::string& sensor, std::optional<double> distance_mm, std::uint16_t code,
                      ls5::SignalState signal, std::chrono::system_clock::time_point time) {
  Sample sample;
  sample.time = time;
  sample.device = "ls5";
  sample.kind = ls5::kind::result;
  sample.set(ls5::channel::code, code);
  sample.set(ls5::channel::distance_mm, distance_mm);
  sample.set(ls5::channel::signal, signal);
  sample.set(ls5::channel::resolution_mm, 0.001);
  return hub::HubItem{0, sensor, sample};
}

TEST(ReadingRows, AReadingIsALineWithTheSensorsNextSeq) {
  ls5_driver_test::TempDir dir;
  auto spool = record::Spool::open((dir.path / "s.spool").string(), 1 << 20);
  ASSERT_TRUE(spool.ok());
  sinks::ReadingRows rows(0);
  const std::chrono::system_clock::time_point at{std::chrono::nanoseconds(1765098000123456789)};
  auto first = rows.row_of(ls5_item("belt", 20.5, 20500, ls5::SignalState::ok, at), **spool);
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(first->sensor, "belt");
  EXPECT_EQ(first->seq, 1u);
  EXPECT_EQ(first->time_ns, 1765098000123456789);
  EXPECT_EQ(first->line,
            "rangekit,family=ls5,sensor=belt,unit=mm value=20.5,suspect=false,seq=1i 1765098000123456789\n");
  // No signal (§8 code 65535) is no reading: no row, and no seq taken for it.
  EXPECT_FALSE(rows.row_of(ls5_item("belt", std::nullopt, 65535, ls5::SignalState::lost, at + 1ms), **spool));
  EXPECT_FALSE(rows.row_of(hub::HubItem{0, "belt", StreamEvent{}}, **spool));
  EXPECT_EQ(rows.skipped(), 1u);
  auto second = rows.row_of(ls5_item("belt", 20.6, 20600, ls5::SignalState::ok, at + 2ms), **spool);
  ASSERT_TRUE(second.has_value());
  EXPECT_EQ(second->seq, 2u);
  auto other = rows.row_of(ls5_item("gate", 1.0, 1000, ls5::SignalState::ok, at + 2ms), **spool);
  ASSERT_TRUE(other.has_value());
  EXPECT_EQ(other->seq, 1u);  // each sensor its own sequence
}

TEST(ReadingRows, AtMostMaxRateHzPerSensor) {
  ls5_driver_test::TempDir dir;
  auto spool = record::Spool::open((dir.path / "s.spool").string(), 1 << 20);
  ASSERT_TRUE(spool.ok());
  sinks::ReadingRows rows(10);  // one per 100 ms
  const auto start = std::chrono::system_clock::now();
  int kept = 0;
  for (int ms = 0; ms < 1000; ms += 10) {
    if (rows.row_of(ls5_item("belt", 20.0, 20000, ls5::SignalState::ok, start + std::chrono::milliseconds(ms)),
                    **spool)) {
      ++kept;
    }
  }
  EXPECT_EQ(kept, 10);  // 0, 100, ... 900 ms
  EXPECT_EQ(rows.skipped(), 90u);
}

}  // namespace
