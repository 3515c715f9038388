#include "rangekit/hub/fanout.hpp"

#include <algorithm>

namespace rangekit::hub {

Subscription::Subscription(std::string sensor_filter, std::size_t capacity, OverflowPolicy policy)
    : filter_(std::move(sensor_filter)), capacity_(std::max<std::size_t>(capacity, 1)), policy_(policy) {}

bool Subscription::offer(const HubItemPtr& item) {
  bool open = true;
  bool woke = false;
  std::function<void()> listener;
  {
    std::lock_guard lock(mutex_);
    if (closed_) return false;
    if (!filter_.empty() && item->sensor != filter_) return true;
    woke = items_.empty();
    if (items_.size() >= capacity_) {
      ++lost_;
      if (policy_ == OverflowPolicy::cut_off) {
        closed_ = true;
        cut_off_ = true;
        open = false;
      } else {
        items_.pop_front();
        items_.push_back(item);
      }
    } else {
      items_.push_back(item);
    }
    if (woke || !open) listener = listener_;
  }
  if (open) {
    ready_.notify_one();
  } else {
    ready_.notify_all();  // the reader learns it was cut off
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

void Fanout::publish(const HubItemPtr& item) {
  std::lock_guard lock(mutex_);
  // Subscriptions only take the item under their own short lock: no subscriber can hold this up.
  auto closed = std::remove_if(subscriptions_.begin(), subscriptions_.end(), [&](const SubscriptionPtr& s) {
    if (s->offer(item)) return false;
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

void SampleRing::push(HubItemPtr item) {
  std::lock_guard lock(mutex_);
  if (items_.size() >= capacity_) {
    evicted_up_to_ = items_.front()->sequence;
    items_.pop_front();
  }
  items_.push_back(std::move(item));
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
