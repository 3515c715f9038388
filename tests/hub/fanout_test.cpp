// Fan-out with bounded per-subscriber queues: a slow subscriber
// loses items, counted for it alone; nobody else is held up.
#include "rangekit/hub/fanout.hpp"
#include "rangekit/uls/family.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <thread>

namespace {

using namespace rangekit::hub;
using namespace std::chrono_literals;

HubItemPtr item(std::uint64_t sequence, const std::string& sensor = "a") {
  rangekit::Sample sample;
  sample.set(rangekit::uls::channel::distance_m, static_cast<double>(sequence));
  return std::make_shared<const HubItem>(HubItem{sequence, sensor, sample});
}

TEST(Fanout, EverySubscriberGetsEveryItemInOrder) {
  Fanout fanout;
  auto first = fanout.subscribe("", 100, OverflowPolicy::drop_oldest);
  auto second = fanout.subscribe("", 100, OverflowPolicy::cut_off);
  for (std::uint64_t i = 1; i <= 50; ++i) fanout.publish(item(i));
  for (const auto& subscription : {first, second}) {
    const auto batch = subscription->take(1000, 0ms);
    ASSERT_EQ(batch.size(), 50u);
    for (std::size_t i = 0; i < batch.size(); ++i) EXPECT_EQ(batch[i]->sequence, i + 1);
    EXPECT_EQ(subscription->lost(), 0u);
  }
}

TEST(Fanout, ASensorFilterPassesOnlyThatSensor) {
  Fanout fanout;
  auto only_b = fanout.subscribe("b", 10, OverflowPolicy::drop_oldest);
  fanout.publish(item(1, "a"));
  fanout.publish(item(2, "b"));
  const auto batch = only_b->take(10, 0ms);
  ASSERT_EQ(batch.size(), 1u);
  EXPECT_EQ(batch[0]->sensor, "b");
}

TEST(Fanout, ASlowSubscriberLosesTheOldestAndTheLossIsCountedForItAlone) {
  Fanout fanout;
  auto slow = fanout.subscribe("", 4, OverflowPolicy::drop_oldest);
  auto keeping_up = fanout.subscribe("", 4, OverflowPolicy::drop_oldest);
  for (std::uint64_t i = 1; i <= 10; ++i) {
    fanout.publish(item(i));
    EXPECT_EQ(keeping_up->take(10, 0ms).size(), 1u);
  }
  const auto batch = slow->take(10, 0ms);
  ASSERT_EQ(batch.size(), 4u);
  EXPECT_EQ(batch.front()->sequence, 7u);  // the newest four are kept
  EXPECT_EQ(slow->lost(), 6u);
  EXPECT_EQ(keeping_up->lost(), 0u);
}

TEST(Fanout, AStalledCutOffSubscriberIsClosedCountedAndForgotten) {
  Fanout fanout;
  auto stalled = fanout.subscribe("", 3, OverflowPolicy::cut_off);
  auto reader = fanout.subscribe("", 3, OverflowPolicy::cut_off);
  for (std::uint64_t i = 1; i <= 5; ++i) {
    fanout.publish(item(i));
    reader->take(10, 0ms);
  }
  EXPECT_TRUE(stalled->closed());
  EXPECT_TRUE(stalled->cut_off());
  EXPECT_EQ(stalled->lost(), 1u);                // item 4 found its queue full; from then on it is no subscriber
  EXPECT_EQ(stalled->take(10, 0ms).size(), 3u);  // what it had stays readable
  EXPECT_EQ(fanout.cut_off_count(), 1u);
  EXPECT_EQ(fanout.subscribers(), 1u);
  EXPECT_FALSE(reader->closed());
}

TEST(Fanout, TakeWakesOnPublishAndOnClose) {
  Fanout fanout;
  auto subscription = fanout.subscribe("", 10, OverflowPolicy::drop_oldest);
  std::thread publisher([&] { fanout.publish(item(1)); });
  const auto batch = subscription->take(10, 10s);  // returns when the item arrives, not after 10 s
  publisher.join();
  ASSERT_EQ(batch.size(), 1u);
  std::thread closer([&] { subscription->close(); });
  EXPECT_TRUE(subscription->take(10, 10s).empty());
  closer.join();
  EXPECT_TRUE(subscription->closed());
  EXPECT_FALSE(subscription->cut_off());
}

TEST(SampleRing, ResumesAfterASequenceAndSaysWhenItemsWereMissed) {
  SampleRing ring(3);
  for (std::uint64_t sequence : {2, 5, 7, 9}) ring.push(item(sequence));  // 2 leaves the ring
  auto since = ring.since(5);
  ASSERT_EQ(since.items.size(), 2u);
  EXPECT_EQ(since.items[0]->sequence, 7u);
  EXPECT_TRUE(since.complete);
  since = ring.since(2);
  EXPECT_EQ(since.items.size(), 3u);
  EXPECT_TRUE(since.complete);  // 2 itself was delivered before
  since = ring.since(1);
  EXPECT_FALSE(since.complete);  // 2 is gone
  EXPECT_TRUE(ring.since(9).items.empty());
  const auto latest = ring.latest(2);
  ASSERT_EQ(latest.size(), 2u);
  EXPECT_EQ(latest[1]->sequence, 9u);
  EXPECT_EQ(ring.latest(10).size(), 3u);
}

}  // namespace

namespace {

using namespace rangekit::hub;
using namespace std::chrono_literals;

// An event loop cannot block in take(): it is told when an item lands in an empty queue
// (once per batch, not per item) and when the subscription ends.
TEST(Fanout, TheListenerHearsOfTheFirstItemOfABatchAndOfTheEnd) {
  Fanout fanout;
  auto subscription = fanout.subscribe("", 2, OverflowPolicy::cut_off);
  int calls = 0;
  subscription->set_listener([&] { ++calls; });
  const auto item = [](std::uint64_t sequence) {
    return std::make_shared<const HubItem>(HubItem{sequence, "a", rangekit::Sample{}});
  };
  fanout.publish(item(1));
  fanout.publish(item(2));
  EXPECT_EQ(calls, 1);  // the second landed in a queue that was not empty
  EXPECT_EQ(subscription->take(10, 0ms).size(), 2u);
  fanout.publish(item(3));
  EXPECT_EQ(calls, 2);
  fanout.publish(item(4));
  fanout.publish(item(5));  // full: cut off
  EXPECT_EQ(calls, 3);
  EXPECT_TRUE(subscription->cut_off());
}

}  // namespace
