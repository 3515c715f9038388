// StreamQueue: the reader's hand-off to the consumer. Never blocks the reader,
// drops the oldest and counts it, wakes a waiting consumer on close, discards
// what is pushed after close until reopened.
#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <thread>
#include <vector>

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

// take_all: a consumer takes everything queued with one wake-up, in
// the order pushed, and sees the same items pop() would have given it one by one.
TEST(StreamQueue, TakeAllHandsOverEverythingQueuedInOrder) {
  StreamQueue<int> queue;
  std::vector<int> batch{99};  // what a previous batch left: replaced, not appended to
  EXPECT_FALSE(queue.take_all(batch, 0ms));
  EXPECT_TRUE(batch.empty());
  for (int i = 1; i <= 3; ++i) queue.push(i);
  ASSERT_TRUE(queue.take_all(batch, 0ms));
  EXPECT_EQ(batch, (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(queue.size(), 0U);
  queue.push(4);
  ASSERT_TRUE(queue.take_all(batch, 0ms));
  EXPECT_EQ(batch, (std::vector<int>{4}));
}

// Mixed with single pops and with drops of the oldest, take_all still gets exactly
// what is left, oldest first; a closed queue still hands over what it holds.
TEST(StreamQueue, TakeAllAfterPopsAndDropsGetsWhatIsLeft) {
  StreamQueue<int> queue(4);
  for (int i = 1; i <= 6; ++i) queue.push(i);  // 1 and 2 dropped
  EXPECT_EQ(queue.dropped(), 2U);
  EXPECT_EQ(queue.pop(0ms), 3);
  queue.close();
  std::vector<int> batch;
  ASSERT_TRUE(queue.take_all(batch, 0ms));
  EXPECT_EQ(batch, (std::vector<int>{4, 5, 6}));
  EXPECT_FALSE(queue.take_all(batch, 0ms));  // closed and drained: at once
}

// A full queue dropping for a long time (no consumer) keeps only its newest `capacity`
// items, in order: the dropped ones do not pile up behind them.
TEST(StreamQueue, ALongOverflowKeepsTheNewestInOrder) {
  StreamQueue<int> queue(100);
  for (int i = 1; i <= 10'000; ++i) queue.push(i);
  EXPECT_EQ(queue.dropped(), 9'900U);
  EXPECT_EQ(queue.size(), 100U);
  std::vector<int> batch;
  ASSERT_TRUE(queue.take_all(batch, 0ms));
  ASSERT_EQ(batch.size(), 100U);
  for (std::size_t i = 0; i < batch.size(); ++i) EXPECT_EQ(batch[i], static_cast<int>(9'901 + i));
}

// With a gather time the consumer woken by the first item takes the ones that joined it
// in the same batch; close() ends an hour's gather at once.
TEST(StreamQueue, AWokenConsumerTakesTheGatheredItemsInOneBatch) {
  StreamQueue<int> queue(16, std::chrono::hours(1));
  std::vector<int> batch;
  bool got = false;
  std::thread consumer([&] { got = queue.take_all(batch, std::chrono::hours(1)); });
  queue.push(1);
  queue.push(2);
  queue.push(3);
  queue.close();
  consumer.join();
  ASSERT_TRUE(got);
  EXPECT_EQ(batch, (std::vector<int>{1, 2, 3}));
}

// push_all: a reader's whole read in one hand-over, in order, dropping the oldest when
// it overflows, and nothing once closed; the reader's vector comes back empty.
TEST(StreamQueue, PushAllQueuesABatchInOrderAndDropsTheOldestWhenFull) {
  StreamQueue<int> queue(4);
  std::vector<int> read{1, 2, 3};
  queue.push_all(read);
  EXPECT_TRUE(read.empty());
  read = {4, 5, 6};
  queue.push_all(read);
  EXPECT_EQ(queue.dropped(), 2U);
  std::vector<int> batch;
  ASSERT_TRUE(queue.take_all(batch, 0ms));
  EXPECT_EQ(batch, (std::vector<int>{3, 4, 5, 6}));
  queue.close();
  read = {7};
  queue.push_all(read);
  EXPECT_EQ(queue.size(), 0U);
}

}  // namespace
}  // namespace rangekit
