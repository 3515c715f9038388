// Which hub items become spool rows: a sample's one reading with its family, unit and the
// sensor's next seq; never a sample without a reading or an event; at most max_rate_hz.
#include "sinks/reading_rows.hpp"

#include <gtest/gtest.h>

#include "ls5_driver/cli_process.hpp"
#include "rangekit/core/family.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/sinks/line_protocol.hpp"

namespace {

using namespace rangekit;
using namespace std::chrono_literals;

// The rows of one item, as the intake takes them.
std::vector<record::SpoolRow> rows_of(sinks::ReadingRows& rows, const hub::HubItem& item, record::Spool& spool) {
  std::vector<record::SpoolRow> out;
  rows.add(item, spool, out);
  return out;
}

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
  sinks::ReadingRows rows(0, sinks::encode_line);
  const std::chrono::system_clock::time_point at{std::chrono::nanoseconds(1765098000123456789)};
  auto first = rows_of(rows, ls5_item("belt", 20.5, 20500, ls5::SignalState::ok, at), **spool);
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].sensor, "belt");
  EXPECT_EQ(first[0].seq, 1u);
  EXPECT_EQ(first[0].time_ns, 1765098000123456789);
  EXPECT_EQ(first[0].line,
            "rangekit,family=ls5,sensor=belt,unit=mm value=20.5,suspect=false,seq=1i 1765098000123456789\n");
  // No signal (§8 code 65535) is no reading: no row, and no seq taken for it.
  EXPECT_TRUE(rows_of(rows, ls5_item("belt", std::nullopt, 65535, ls5::SignalState::lost, at + 1ms), **spool).empty());
  EXPECT_TRUE(rows_of(rows, hub::HubItem{0, "belt", StreamEvent{}}, **spool).empty());
  EXPECT_EQ(rows.skipped(), 1u);
  auto second = rows_of(rows, ls5_item("belt", 20.6, 20600, ls5::SignalState::ok, at + 2ms), **spool);
  ASSERT_EQ(second.size(), 1u);
  EXPECT_EQ(second[0].seq, 2u);
  auto other = rows_of(rows, ls5_item("gate", 1.0, 1000, ls5::SignalState::ok, at + 2ms), **spool);
  ASSERT_EQ(other.size(), 1u);
  EXPECT_EQ(other[0].seq, 1u);  // each sensor its own sequence
}

TEST(ReadingRows, WithMaxRateHzEachWindowIsOneRowOfItsCountMinMaxAndLast) {
  ls5_driver_test::TempDir dir;
  auto spool = record::Spool::open((dir.path / "s.spool").string(), 1 << 20);
  ASSERT_TRUE(spool.ok());
  sinks::ReadingRows rows(10, sinks::encode_line);  // windows of 100 ms of the system clock
  // 1765098000.000 s is the start of a window: 100 readings 10 ms apart span ten windows.
  const std::chrono::system_clock::time_point start{std::chrono::seconds(1765098000)};
  std::vector<record::SpoolRow> out;
  for (int ms = 0; ms < 1000; ms += 10) {
    const double mm = 20.0 + (ms % 100) / 10 * 0.5;  // 20.0 .. 24.5 in each window
    rows.add(ls5_item("belt", mm, 20000, ls5::SignalState::ok, start + std::chrono::milliseconds(ms)), **spool, out);
  }
  ASSERT_EQ(out.size(), 9u);  // the tenth window is still open
  EXPECT_EQ(out[0].seq, 1u);
  EXPECT_EQ(out[8].seq, 9u);
  // Written at its last reading's time (90 ms), with count/min/max beside value (the last).
  EXPECT_EQ(out[0].line,
            "rangekit,family=ls5,sensor=belt,unit=mm value=24.5,suspect=false,seq=1i,count=10i,min=20,max=24.5 "
            "1765098000090000000\n");
  // A sensor gone quiet: its window (900-1000 ms) is written once a whole period has passed after it.
  rows.close_windows(start + 1099ms, **spool, out);
  EXPECT_EQ(out.size(), 9u);
  rows.close_windows(start + 1100ms, **spool, out);
  ASSERT_EQ(out.size(), 10u);
  EXPECT_EQ(out[9].seq, 10u);
}

TEST(ReadingRows, AWindowOfOnlySuspectReadingsIsItsLastMarkedSuspect) {
  ls5_driver_test::TempDir dir;
  auto spool = record::Spool::open((dir.path / "s.spool").string(), 1 << 20);
  ASSERT_TRUE(spool.ok());
  sinks::ReadingRows rows(10, sinks::encode_line);
  const std::chrono::system_clock::time_point start{std::chrono::seconds(1765098000)};
  std::vector<record::SpoolRow> out;
  auto odd = ls5_item("belt", 999.0, 20000, ls5::SignalState::ok, start + 10ms);
  std::get<Sample>(odd.item).suspect = true;
  rows.add(odd, **spool, out);
  auto good = ls5_item("belt", 20.0, 20000, ls5::SignalState::ok, start + 110ms);
  rows.add(good, **spool, out);
  std::get<Sample>(odd.item).time = start + 120ms;
  rows.add(odd, **spool, out);  // suspect: kept out of the second window's figures
  rows.close_all(**spool, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].line, "rangekit,family=ls5,sensor=belt,unit=mm value=999,suspect=true,seq=1i 1765098000010000000\n");
  EXPECT_EQ(out[1].line,
            "rangekit,family=ls5,sensor=belt,unit=mm value=20,suspect=false,seq=2i,count=1i,min=20,max=20 "
            "1765098000110000000\n");
}

}  // namespace
