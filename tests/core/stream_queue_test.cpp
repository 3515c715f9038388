// StreamQueue: the reader's hand-off to the consumer. Never blocks the reader,
// drops the oldest and counts it, wakes a waiting consumer on close, discards
// what is pushed after close until reopened.
#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <thread>

#include "rangekit/core/stream_queue.hpp"

namespace rangekit {
namespace {

using namespace std::chrono_literals;

TEST(StreamQueue, FullQueueDropsTheOldestAndCountsIt) {
  StreamQueue<int> queue(3);
  for (int i = 1; i <= 5; ++i) queue.push(i);
  EXPECT_EQ(queue.dropped(), 2U);
  EXPECT_EQ(queue.pop(0ms), 3);
  EXPECT_EQ(queue.pop(0ms), 4);
  EXPECT_EQ(queue.pop(0ms), 5);
  EXPECT_EQ(queue.pop(0ms), std::nullopt);
}

TEST(StreamQueue, CloseWakesAWaitingConsumerAndKeepsQueuedItems) {
  StreamQueue<int> queue;
  queue.push(7);
  queue.close();
  EXPECT_EQ(queue.pop(0ms), 7);  // queued before close: still delivered
  std::optional<int> got{0};
  StreamQueue<int> empty;
  std::thread consumer([&] { got = empty.pop(60s); });
  empty.close();  // the consumer returns now, not after 60 s
  consumer.join();
  EXPECT_EQ(got, std::nullopt);
}

TEST(StreamQueue, PushAfterCloseIsDiscardedUntilReopened) {
  StreamQueue<int> queue;
  queue.close();
  queue.push(1);
  EXPECT_EQ(queue.size(), 0U);
  EXPECT_EQ(queue.dropped(), 0U);  // not a loss: the stream had ended
  queue.reopen();
  queue.push(2);
  EXPECT_EQ(queue.pop(0ms), 2);
}

// With a gather time a consumer woken by the first item lets the next ones join it;
// a gather of an hour must still end at close(), with nothing lost and in order.
// (Fewer wake-ups is a speed figure: bench/, not here.)
TEST(StreamQueue, AWokenConsumerLetsTheNextItemsGatherBeforeItTakesOne) {
  StreamQueue<int> queue(16, std::chrono::hours(1));
  std::optional<int> first;
  std::thread consumer([&] { first = queue.pop(std::chrono::hours(1)); });
  queue.push(1);
  queue.push(2);
  queue.push(3);
  queue.close();  // ends the gather at once
  consumer.join();
  EXPECT_EQ(first, 1);
  EXPECT_EQ(queue.pop(0ms), 2);
  EXPECT_EQ(queue.pop(0ms), 3);
  EXPECT_EQ(queue.pop(0ms), std::nullopt);
}

// Pushes notify only when the queue fills from empty: two consumers waiting together
// still both get one of two items pushed back to back.
TEST(StreamQueue, TwoWaitingConsumersEachGetOneOfTwoItems) {
  StreamQueue<int> queue;
  std::optional<int> got[2];
  std::thread a([&] { got[0] = queue.pop(std::chrono::hours(1)); });
  std::thread b([&] { got[1] = queue.pop(std::chrono::hours(1)); });
  queue.push(1);
  queue.push(2);
  a.join();
  b.join();
  ASSERT_TRUE(got[0] && got[1]);
  EXPECT_EQ(*got[0] + *got[1], 3);
}

}  // namespace
}  // namespace rangekit
