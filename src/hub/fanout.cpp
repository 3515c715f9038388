#include "rangekit/hub/fanout.hpp"

#include <algorithm>

namespace rangekit::hub {

Subscription::Subscription(std::string sensor_filter, std::size_t capacity, OverflowPolicy policy)
    : Subscription(
          sensor_filter.empty() ? std::vector<std::string>{} : std::vector<std::string>{std::move(sensor_filter)},
          capacity, policy) {}

Subscription::Subscription(std::vector<std::string> sensors, std::size_t capacity, OverflowPolicy policy)
    : sensors_(std::move(sensors)), capacity_(std::max<std::size_t>(capacity, 1)), policy_(policy) {
  std::sort(sensors_.begin(), sensors_.end());
}

bool Subscription::wants(std::string_view sensor) const noexcept {
  return sensors_.empty() || std::binary_search(sensors_.begin(), sensors_.end(), sensor, std::less<>{});
}

bool Subscription::offer(const HubItemPtr& item) { return offer_all(std::span<const HubItemPtr>(&item, 1)); }

bool Subscription::offer_all(std::span<const HubItemPtr> items) { return offer(items, true); }

bool Subscription::offer_wanted(std::span<const HubItemPtr> items) { return offer(items, false); }

bool Subscription::offer(std::span<const HubItemPtr> items, bool filtered) {
  bool open = true;
  bool woke = false;
  std::function<void()> listener;
  {
    std::lock_guard lock(mutex_);
    if (closed_) return false;
    const bool was_empty = items_.empty();
    for (const HubItemPtr& item : items) {
      if (filtered && !wants(item->sensor)) continue;
      if (items_.size() >= capacity_) {
        ++lost_;
        if (policy_ == OverflowPolicy::cut_off) {
          closed_ = true;
          cut_off_ = true;
          open = false;
          break;
        }
        items_.pop_front();
      }
      items_.push_back(item);
    }
    // A reader waits only for an empty queue to fill: the items after the first find it awake.
    woke = was_empty && !items_.empty();
    if (woke || !open) listener = listener_;
  }
  if (!open) {
    ready_.notify_all();  // the reader learns it was cut off
  } else if (woke) {
    ready_.notify_one();
  }
  if (listener) listener();
  return open;
}

void Subscription::set_listener(std::function<void()> listener) {
  std::lock_guard lock(mutex_);
  listener_ = std::move(listener);
}

std::vector<HubItemPtr> Subscription::take(std::size_t max, std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  // No wait at all for a zero timeout: a condition wait with an expired deadline still
  // sleeps in the kernel, once per flush of every SSE client (perf, docs/service.md).
  if (timeout.count() > 0) ready_.wait_for(lock, timeout, [this] { return !items_.empty() || closed_; });
  std::vector<HubItemPtr> batch;
  const std::size_t count = std::min(max, items_.size());
  batch.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    batch.push_back(std::move(items_.front()));
    items_.pop_front();
  }
  return batch;
}

void Subscription::close() {
  std::function<void()> listener;
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    closed_ = true;
    listener = std::move(listener_);
  }
  ready_.notify_all();
  if (listener) listener();
}

bool Subscription::closed() const {
  std::lock_guard lock(mutex_);
  return closed_;
}

bool Subscription::cut_off() const {
  std::lock_guard lock(mutex_);
  return cut_off_;
}

std::uint64_t Subscription::lost() const {
  std::lock_guard lock(mutex_);
  return lost_;
}

std::size_t Subscription::queued() const {
  std::lock_guard lock(mutex_);
  return items_.size();
}

SubscriptionPtr Fanout::subscribe(std::string sensor_filter, std::size_t capacity, OverflowPolicy policy) {
  auto subscription = std::make_shared<Subscription>(std::move(sensor_filter), capacity, policy);
  std::lock_guard lock(mutex_);
  subscriptions_.push_back(subscription);
  return subscription;
}

SubscriptionPtr Fanout::subscribe(std::vector<std::string> sensors, std::size_t capacity, OverflowPolicy policy) {
  auto subscription = std::make_shared<Subscription>(std::move(sensors), capacity, policy);
  std::lock_guard lock(mutex_);
  subscriptions_.push_back(subscription);
  return subscription;
}

void Fanout::publish(const HubItemPtr& item) { publish_all(std::span<const HubItemPtr>(&item, 1)); }

void Fanout::publish_all(std::span<const HubItemPtr> items) {
  if (items.empty()) return;
  std::lock_guard lock(mutex_);
  // Subscriptions only take the items under their own short lock: no subscriber can hold this up.
  auto closed = std::remove_if(subscriptions_.begin(), subscriptions_.end(), [&](const SubscriptionPtr& s) {
    if (s->offer_all(items)) return false;
    if (s->cut_off()) ++cut_off_;
    return true;
  });
  subscriptions_.erase(closed, subscriptions_.end());
}

void Fanout::publish_run(std::string_view sensor, std::span<const HubItemPtr> items) {
  if (items.empty()) return;
  std::lock_guard lock(mutex_);
  auto closed = std::remove_if(subscriptions_.begin(), subscriptions_.end(), [&](const SubscriptionPtr& s) {
    if (!s->wants(sensor) || s->offer_wanted(items)) return false;
    if (s->cut_off()) ++cut_off_;
    return true;
  });
  subscriptions_.erase(closed, subscriptions_.end());
}

std::size_t Fanout::subscribers() const {
  std::lock_guard lock(mutex_);
  return subscriptions_.size();
}

std::uint64_t Fanout::cut_off_count() const {
  std::lock_guard lock(mutex_);
  return cut_off_;
}

SampleRing::SampleRing(std::size_t capacity) : capacity_(std::max<std::size_t>(capacity, 1)) {}

void SampleRing::push(HubItemPtr item) { push_all(std::span<const HubItemPtr>(&item, 1)); }

void SampleRing::push_all(std::span<const HubItemPtr> items) {
  std::lock_guard lock(mutex_);
  for (const HubItemPtr& item : items) {
    if (items_.size() >= capacity_) {
      evicted_up_to_ = items_.front()->sequence;
      items_.pop_front();
    }
    items_.push_back(item);
  }
}

SampleRing::Since SampleRing::since(std::uint64_t after) const {
  std::lock_guard lock(mutex_);
  Since result;
  result.complete = after >= evicted_up_to_;
  auto first =
      std::upper_bound(items_.begin(), items_.end(), after,
                       [](std::uint64_t sequence, const HubItemPtr& item) { return sequence < item->sequence; });
  result.items.assign(first, items_.end());
  return result;
}

std::vector<HubItemPtr> SampleRing::latest(std::size_t count) const {
  std::lock_guard lock(mutex_);
  const std::size_t n = std::min(count, items_.size());
  return {items_.end() - static_cast<std::ptrdiff_t>(n), items_.end()};
}

std::size_t SampleRing::size() const {
  std::lock_guard lock(mutex_);
  return items_.size();
}

}  // namespace rangekit::hub
