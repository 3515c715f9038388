// Fan-out of one sensor's samples and events to many subscribers (SSE clients,
// the MQTT bridge, captures). Each subscriber has its own bounded queue: the
// publisher never waits on a subscriber, a slow one loses items and the loss is
// counted for it alone, and the others are not slowed down.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rangekit/core/sample.hpp"

namespace rangekit::hub {

// One sample or event of one sensor, numbered by the hub. The sequence is one
// counter for the whole hub, so "everything after N" means the same on a
// sensor's stream and on the stream of all sensors (SSE Last-Event-ID).
struct HubItem {
  std::uint64_t sequence = 0;
  std::string sensor;
  StreamItem item;
};
using HubItemPtr = std::shared_ptr<const HubItem>;  // shared by every queue, copied never

// What a full queue does with the next item.
enum class OverflowPolicy : std::uint8_t {
  drop_oldest,  // keep going, count the loss (a capture prefers the newest; MQTT too)
  cut_off,      // close the subscription, count the loss (an SSE client resumes with Last-Event-ID)
};

class Subscription {
 public:
  // `sensor_filter` empty: every sensor's items.
  Subscription(std::string sensor_filter, std::size_t capacity, OverflowPolicy policy);
  // The items of these sensors only; none named: every sensor's.
  Subscription(std::vector<std::string> sensors, std::size_t capacity, OverflowPolicy policy);

  // Waits up to `timeout` for items and takes up to `max` of them at once (one
  // wake-up per batch). Empty on timeout, or when closed and drained.
  std::vector<HubItemPtr> take(std::size_t max, std::chrono::milliseconds timeout);
  // Ends the subscription; take() returns what is queued, then nothing.
  void close();
  [[nodiscard]] bool closed() const;
  // True when the subscription was closed because its queue overflowed (cut_off).
  [[nodiscard]] bool cut_off() const;
  [[nodiscard]] std::uint64_t lost() const;  // items this subscriber never got
  [[nodiscard]] std::size_t queued() const;
  // Whether items of `sensor` are for this subscription (fixed at its start: no lock).
  [[nodiscard]] bool wants(std::string_view sensor) const noexcept;

  // For the fan-out: never blocks. False once the subscription is closed.
  bool offer(const HubItemPtr& item);
  // The items in order under one lock, with at most one wake-up of the reader: a sensor's
  // batch (an LS5 UDP packet is 168 samples) costs one hand-over, not one per sample.
  bool offer_all(std::span<const HubItemPtr> items);
  // offer_all of items the caller knows it wants (one sensor's run, wants() asked once).
  bool offer_wanted(std::span<const HubItemPtr> items);

  // Called (on the publisher's thread, outside any lock) when an item lands in an
  // empty queue and when the subscription closes: an event loop that cannot block in
  // take() schedules its read from here. Must not call back into the subscription's
  // publisher. Set before the first item can arrive, or accept a missed first call.
  void set_listener(std::function<void()> listener);

 private:
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<HubItemPtr> items_;
  bool offer(std::span<const HubItemPtr> items, bool filtered);
  std::vector<std::string> sensors_;  // sorted; empty for every sensor
  std::size_t capacity_;
  OverflowPolicy policy_;
  std::uint64_t lost_ = 0;
  bool closed_ = false;
  bool cut_off_ = false;
  std::function<void()> listener_;
};
using SubscriptionPtr = std::shared_ptr<Subscription>;

class Fanout {
 public:
  // `sensor_filter` empty: every sensor's items.
  SubscriptionPtr subscribe(std::string sensor_filter, std::size_t capacity, OverflowPolicy policy);
  // The items of these sensors (none named: every sensor's), in one queue.
  SubscriptionPtr subscribe(std::vector<std::string> sensors, std::size_t capacity, OverflowPolicy policy);
  // Hands `item` to every open subscription that wants it; closed ones are forgotten.
  void publish(const HubItemPtr& item);
  // The items in order, each subscription taking them all under one lock.
  void publish_all(std::span<const HubItemPtr> items);
  // publish_all of items all of `sensor`: each subscription is asked once whether it wants them.
  void publish_run(std::string_view sensor, std::span<const HubItemPtr> items);
  [[nodiscard]] std::size_t subscribers() const;
  // Subscriptions closed because they fell behind (cut_off), since the start.
  [[nodiscard]] std::uint64_t cut_off_count() const;

 private:
  mutable std::mutex mutex_;
  std::vector<SubscriptionPtr> subscriptions_;
  std::uint64_t cut_off_ = 0;
};

// The last `capacity` items of one sensor, for GET …/samples and to resume an
// SSE stream from Last-Event-ID.
class SampleRing {
 public:
  explicit SampleRing(std::size_t capacity);
  void push(HubItemPtr item);
  void push_all(std::span<const HubItemPtr> items);
  // Items with a sequence above `after`, oldest first. `complete` is false when
  // items after `after` have already left the ring (the client missed some).
  struct Since {
    std::vector<HubItemPtr> items;
    bool complete = true;
  };
  [[nodiscard]] Since since(std::uint64_t after) const;
  [[nodiscard]] std::vector<HubItemPtr> latest(std::size_t count) const;
  [[nodiscard]] std::size_t size() const;

 private:
  mutable std::mutex mutex_;
  std::deque<HubItemPtr> items_;
  std::size_t capacity_;
  std::uint64_t evicted_up_to_ = 0;  // the highest sequence that left the ring
};

}  // namespace rangekit::hub
