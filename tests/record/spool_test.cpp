// The spool on disk: bounded (the oldest dropped and counted), and what it holds, with each
// sensor's last sequence, survives closing and reopening.
#include "rangekit/record/spool.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "record/temp_dir.hpp"

namespace {

using namespace rangekit::record;
using rangekit::record::testing::TempDir;

std::vector<SpoolRow> rows_of(Spool& spool, const std::string& sensor, int count) {
  std::vector<SpoolRow> rows;
  for (int i = 0; i < count; ++i) {
    SpoolRow row;
    row.sensor = sensor;
    row.seq = spool.next_seq(sensor);
    row.time_ns = 1000 + static_cast<std::int64_t>(row.seq);
    row.line = "rangekit,sensor=" + sensor + " seq=" + std::to_string(row.seq) + "i\n";
    rows.push_back(std::move(row));
  }
  return rows;
}

TEST(Spool, AtItsCapDropsTheOldestAndCountsThem) {
  TempDir dir;
  SpoolRow sample;
  sample.sensor = "belt";
  sample.line = "rangekit,sensor=belt seq=10i\n";  // every row below is this long (seq 10..34)
  const std::uint64_t cap = Spool::row_bytes(sample) * 10;
  auto spool = Spool::open(dir.file("s.spool"), cap);
  ASSERT_TRUE(spool.ok()) << spool.error().message;
  for (int i = 0; i < 9; ++i) (void)(*spool)->next_seq("belt");  // sequences from 10: equal lengths
  auto dropped = (*spool)->append(rows_of(**spool, "belt", 25));
  ASSERT_TRUE(dropped.ok()) << dropped.error().message;
  EXPECT_EQ(*dropped, 15u);
  const SpoolStats stats = (*spool)->stats();
  EXPECT_EQ(stats.rows, 10u);
  EXPECT_EQ(stats.dropped, 15u);
  EXPECT_LE(stats.bytes, cap);
  auto oldest = (*spool)->oldest(100);
  ASSERT_TRUE(oldest.ok());
  ASSERT_EQ(oldest->size(), 10u);
  EXPECT_EQ(oldest->front().seq, 25u);  // 10..24 dropped
  EXPECT_EQ(oldest->back().seq, 34u);
  EXPECT_EQ(stats.oldest_time_ns, 1025);
}

TEST(Spool, SurvivesReopeningWithItsRowsAndSequences) {
  TempDir dir;
  const std::string path = dir.file("s.spool");
  {
    auto spool = Spool::open(path, 1 << 20);
    ASSERT_TRUE(spool.ok()) << spool.error().message;
    ASSERT_TRUE((*spool)->append(rows_of(**spool, "belt", 3)).ok());
    ASSERT_TRUE((*spool)->append(rows_of(**spool, "bay A", 2)).ok());
    auto oldest = (*spool)->oldest(1);
    ASSERT_TRUE(oldest.ok() && oldest->size() == 1);
    ASSERT_TRUE((*spool)->remove_through(oldest->front().id).ok());  // belt 1 confirmed
    EXPECT_EQ((*spool)->stats().rows, 4u);
  }
  auto spool = Spool::open(path, 1 << 20);
  ASSERT_TRUE(spool.ok()) << spool.error().message;
  const SpoolStats stats = (*spool)->stats();
  EXPECT_EQ(stats.rows, 4u);
  EXPECT_EQ(stats.oldest_time_ns, 1002);
  auto rows = (*spool)->oldest(10);
  ASSERT_TRUE(rows.ok());
  ASSERT_EQ(rows->size(), 4u);
  EXPECT_EQ((*rows)[0].sensor, "belt");
  EXPECT_EQ((*rows)[0].seq, 2u);
  EXPECT_EQ((*rows)[0].line, "rangekit,sensor=belt seq=2i\n");
  EXPECT_EQ((*rows)[3].sensor, "bay A");
  EXPECT_EQ((*rows)[3].seq, 2u);
  // Sequences go on where they were, also for rows already confirmed.
  EXPECT_EQ((*spool)->next_seq("belt"), 4u);
  EXPECT_EQ((*spool)->next_seq("bay A"), 3u);
  EXPECT_EQ((*spool)->next_seq("silo"), 1u);
}

TEST(Spool, RemovesOnlyWhatWasConfirmed) {
  TempDir dir;
  auto spool = Spool::open(dir.file("s.spool"), 1 << 20);
  ASSERT_TRUE(spool.ok());
  ASSERT_TRUE((*spool)->append(rows_of(**spool, "belt", 5)).ok());
  auto first = (*spool)->oldest(2);
  ASSERT_TRUE(first.ok() && first->size() == 2);
  ASSERT_TRUE((*spool)->append(rows_of(**spool, "belt", 1)).ok());  // arrives while the two are sent
  ASSERT_TRUE((*spool)->remove_through(first->back().id).ok());
  auto rest = (*spool)->oldest(10);
  ASSERT_TRUE(rest.ok());
  ASSERT_EQ(rest->size(), 4u);
  EXPECT_EQ(rest->front().seq, 3u);
  EXPECT_EQ(rest->back().seq, 6u);
  EXPECT_EQ((*spool)->stats().rows, 4u);
  // Rows after those already handed out (in flight, not yet confirmed).
  auto after = (*spool)->oldest(10, rest->front().id);
  ASSERT_TRUE(after.ok());
  ASSERT_EQ(after->size(), 3u);
  EXPECT_EQ(after->front().seq, 4u);
}

// remove() counts off the sizes of the rows it is given instead of reading them back; what it
// leaves is what a count of the file says, also when the cap dropped some of those rows
// between the read and the removal.
TEST(Spool, RemovingTheRowsReadLeavesTheCountsOfTheFile) {
  TempDir dir;
  const std::string path = dir.file("s.spool");
  SpoolRow sample;
  sample.sensor = "belt";
  sample.line = "rangekit,sensor=belt seq=10i\n";
  auto spool = Spool::open(path, Spool::row_bytes(sample) * 20);
  ASSERT_TRUE(spool.ok()) << spool.error().message;
  for (int i = 0; i < 9; ++i) (void)(*spool)->next_seq("belt");  // sequences from 10: equal lengths
  const auto counted = [&] {
    auto reopened = Spool::open(path, 1 << 20);
    EXPECT_TRUE(reopened.ok());
    return reopened ? (*reopened)->stats() : SpoolStats{};
  };
  ASSERT_TRUE((*spool)->append(rows_of(**spool, "belt", 12)).ok());
  auto first = (*spool)->oldest(5);
  ASSERT_TRUE(first.ok() && first->size() == 5);
  ASSERT_TRUE((*spool)->remove(*first).ok());
  SpoolStats stats = (*spool)->stats();
  EXPECT_EQ(stats.rows, 7u);
  EXPECT_EQ(stats.bytes, counted().bytes);
  EXPECT_EQ(stats.oldest_time_ns, 1015);

  // Read while the cap drops the oldest: 7 + 16 rows over a cap of 20 drop 3 of the 5 read.
  auto second = (*spool)->oldest(5);
  ASSERT_TRUE(second.ok() && second->size() == 5);
  auto dropped = (*spool)->append(rows_of(**spool, "belt", 16));
  ASSERT_TRUE(dropped.ok());
  EXPECT_EQ(*dropped, 3u);
  ASSERT_TRUE((*spool)->remove(*second).ok());
  stats = (*spool)->stats();
  const SpoolStats file = counted();
  EXPECT_EQ(stats.rows, 18u);
  EXPECT_EQ(stats.rows, file.rows);
  EXPECT_EQ(stats.bytes, file.bytes);
  EXPECT_EQ(stats.oldest_time_ns, file.oldest_time_ns);
  EXPECT_EQ(stats.oldest_time_ns, 1020);

  // Rows the spool holds before those given go too, as remove_through would; counted from the file.
  auto rest = (*spool)->oldest(10, (*spool)->oldest(1)->front().id);
  ASSERT_TRUE(rest.ok() && rest->size() == 10);
  ASSERT_TRUE((*spool)->remove(*rest).ok());
  EXPECT_EQ((*spool)->stats().rows, 7u);
  EXPECT_EQ((*spool)->stats().bytes, counted().bytes);
}

}  // namespace
