// A sensor's MQTT spool: readings numbered by seq, published after those in flight, and
// forgotten only in order once the broker acknowledged them; a new session sends again
// what was not acknowledged.
#include "mqtt/reading_spool.hpp"

#include <gtest/gtest.h>

#include "ls5_driver/cli_process.hpp"

namespace {

using namespace rangekit;

std::unique_ptr<mqtt::ReadingSpool> open_spool(const ls5_driver_test::TempDir& dir) {
  auto spool = mqtt::ReadingSpool::open((dir.path / "r.spool").string(), 1 << 20, "belt");
  EXPECT_TRUE(spool.ok()) << (spool.ok() ? "" : spool.error().message);
  return spool ? std::move(*spool) : nullptr;
}

TEST(ReadingSpool, EachReadingCarriesItsSensorsSeqFirst) {
  ls5_driver_test::TempDir dir;
  auto spool = open_spool(dir);
  ASSERT_TRUE(spool);
  ASSERT_TRUE(spool->store({R"({"time":"t","distance_mm":20.5})", "{}"}, std::chrono::system_clock::now()).ok());
  auto rows = spool->next(10);
  ASSERT_TRUE(rows.ok());
  ASSERT_EQ(rows->size(), 2u);
  EXPECT_EQ((*rows)[0].line, R"({"seq":1,"time":"t","distance_mm":20.5})");
  EXPECT_EQ((*rows)[1].line, R"({"seq":2})");
}

TEST(ReadingSpool, ForgetsOnlyTheAcknowledgedPrefix) {
  ls5_driver_test::TempDir dir;
  auto spool = open_spool(dir);
  ASSERT_TRUE(spool);
  ASSERT_TRUE(spool->store({"{}", "{}", "{}", "{}"}, std::chrono::system_clock::now()).ok());
  auto first = spool->next(3);
  ASSERT_TRUE(first.ok());
  ASSERT_EQ(first->size(), 3u);
  for (std::size_t i = 0; i < first->size(); ++i) spool->sent(static_cast<int>(i + 10), (*first)[i].id);
  EXPECT_EQ(spool->in_flight(), 3u);
  // What is in flight is not handed out again: only the fourth is next.
  auto after = spool->next(10);
  ASSERT_TRUE(after.ok());
  ASSERT_EQ(after->size(), 1u);
  EXPECT_EQ(after->front().line, R"({"seq":4})");
  // The second acknowledged before the first: nothing can leave the disk yet.
  spool->acknowledged(11);
  ASSERT_TRUE(spool->forget_acknowledged().ok());
  EXPECT_EQ(spool->stats().rows, 4u);
  spool->acknowledged(10);
  ASSERT_TRUE(spool->forget_acknowledged().ok());
  EXPECT_EQ(spool->stats().rows, 2u);  // seq 3 waits for its acknowledgement, seq 4 was never sent
  EXPECT_EQ(spool->in_flight(), 1u);
}

TEST(ReadingSpool, RowsHandedOutButNotSentComeAgainAndNewOnesAfterThem) {
  ls5_driver_test::TempDir dir;
  auto spool = open_spool(dir);
  ASSERT_TRUE(spool);
  ASSERT_TRUE(spool->store({"{}", "{}"}, std::chrono::system_clock::now()).ok());
  auto rows = spool->next(10);
  ASSERT_TRUE(rows.ok() && rows->size() == 2);
  spool->sent(1, rows->front().id);  // the session took only the first
  auto again = spool->next(10);
  ASSERT_TRUE(again.ok());
  ASSERT_EQ(again->size(), 1u);
  EXPECT_EQ(again->front().line, R"({"seq":2})");
  spool->sent(2, again->front().id);
  auto none = spool->next(10);
  ASSERT_TRUE(none.ok());
  EXPECT_TRUE(none->empty());
  ASSERT_TRUE(spool->store({"{}"}, std::chrono::system_clock::now()).ok());
  auto fresh = spool->next(10);
  ASSERT_TRUE(fresh.ok());
  ASSERT_EQ(fresh->size(), 1u);
  EXPECT_EQ(fresh->front().line, R"({"seq":3})");
}

TEST(ReadingSpool, ANewSessionSendsAgainWhatWasNotAcknowledged) {
  ls5_driver_test::TempDir dir;
  auto spool = open_spool(dir);
  ASSERT_TRUE(spool);
  ASSERT_TRUE(spool->store({"{}", "{}", "{}"}, std::chrono::system_clock::now()).ok());
  auto rows = spool->next(3);
  ASSERT_TRUE(rows.ok());
  for (std::size_t i = 0; i < rows->size(); ++i) spool->sent(static_cast<int>(i + 1), (*rows)[i].id);
  spool->acknowledged(1);
  spool->acknowledged(3);  // out of order: seq 2 is still in flight
  ASSERT_TRUE(spool->forget_acknowledged().ok());
  spool->resend_in_flight();
  spool->acknowledged(2);  // of the old session: its message goes again
  auto again = spool->next(10);
  ASSERT_TRUE(again.ok());
  ASSERT_EQ(again->size(), 2u);
  EXPECT_EQ((*again)[0].line, R"({"seq":2})");
  EXPECT_EQ((*again)[1].line, R"({"seq":3})");  // acknowledged, but the spool forgets in order only
}

TEST(ReadingSpool, ARestartResendsTheSpoolAndSeqGoesOn) {
  ls5_driver_test::TempDir dir;
  {
    auto spool = open_spool(dir);
    ASSERT_TRUE(spool);
    ASSERT_TRUE(spool->store({"{}", "{}"}, std::chrono::system_clock::now()).ok());
    auto rows = spool->next(1);
    ASSERT_TRUE(rows.ok() && rows->size() == 1);
    spool->sent(5, rows->front().id);  // never acknowledged: the service stopped
  }
  auto spool = open_spool(dir);
  ASSERT_TRUE(spool);
  ASSERT_TRUE(spool->store({"{}"}, std::chrono::system_clock::now()).ok());
  auto rows = spool->next(10);
  ASSERT_TRUE(rows.ok());
  ASSERT_EQ(rows->size(), 3u);
  EXPECT_EQ((*rows)[0].line, R"({"seq":1})");
  EXPECT_EQ((*rows)[2].line, R"({"seq":3})");
}

TEST(ReadingSpool, TwoSensorsNeverShareAFile) {
  EXPECT_EQ(mqtt::reading_spool_name("rangekit", "belt-2"), "mqtt-rangekit-belt-2.spool");
  const std::string spaced = mqtt::reading_spool_name("rangekit", "bay A");
  const std::string underscored = mqtt::reading_spool_name("rangekit", "bay_A");
  EXPECT_NE(spaced, underscored);
  EXPECT_EQ(spaced.rfind("mqtt-rangekit-bay_A-", 0), 0u) << spaced;
  EXPECT_EQ(mqtt::reading_spool_name("x", "../etc").find('/'), std::string::npos);
}

}  // namespace
