// A bounded hand-off between a reader thread and a consumer. The reader never
// waits on the consumer: when the queue is full the oldest item is dropped and
// counted, so a slow consumer loses records visibly instead of stalling the port.
// With a gather time, a consumer that found the queue empty is woken by the first
// item and then lets the next ones collect for that long before it takes it: one
// wake-up per batch instead of one per record, for at most that much latency.
#pragma once

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <utility>

namespace rangekit {

template <class T>
class StreamQueue {
 public:
  explicit StreamQueue(std::size_t capacity = 65536, std::chrono::microseconds gather = {})
      : capacity_(capacity == 0 ? 1 : capacity), gather_(gather) {}

  // Never blocks on the consumer. Items pushed after close() are discarded: the
  // consumer has been told the stream ended.
  void push(T item) {
    {
      std::lock_guard lock(mutex_);
      if (closed_) return;
      if (items_.size() >= capacity_) {
        items_.pop_front();
        ++dropped_;
      }
      items_.push_back(std::move(item));
      // Consumers wait only for an empty queue to fill (or for the end of a gather):
      // the pushes after the first find nobody to wake.
      if (items_.size() > 1) return;
    }
    ready_.notify_all();
  }

  // Waits up to `timeout` for an item; nullopt on timeout or once closed and empty.
  std::optional<T> pop(std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    const auto deadline = std::chrono::steady_clock::now() + std::min(timeout, std::chrono::milliseconds(86'400'000));
    while (items_.empty()) {
      if (!ready_.wait_until(lock, deadline, [this] { return !items_.empty() || closed_; })) return std::nullopt;
      if (items_.empty()) return std::nullopt;  // closed and drained
      // Woken for one item: let the next ones join it (a close ends the wait). Another
      // consumer may take it meanwhile; then this one waits on.
      if (gather_.count() > 0) ready_.wait_for(lock, gather_, [this] { return closed_ || items_.empty(); });
    }
    T item = std::move(items_.front());
    items_.pop_front();
    return item;
  }

  // Wakes every waiting consumer; items already queued can still be popped.
  void close() {
    {
      std::lock_guard lock(mutex_);
      closed_ = true;
    }
    ready_.notify_all();
  }

  // Takes items again (a source that restarts its stream on the same queue).
  void reopen() {
    std::lock_guard lock(mutex_);
    closed_ = false;
  }

  // Drops what is queued without counting it lost (a stream that failed to start).
  void clear() {
    std::lock_guard lock(mutex_);
    items_.clear();
  }

  [[nodiscard]] bool closed() const {
    std::lock_guard lock(mutex_);
    return closed_;
  }
  [[nodiscard]] std::uint64_t dropped() const {
    std::lock_guard lock(mutex_);
    return dropped_;
  }
  [[nodiscard]] std::size_t size() const {
    std::lock_guard lock(mutex_);
    return items_.size();
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<T> items_;
  std::size_t capacity_;
  std::chrono::microseconds gather_;
  std::uint64_t dropped_ = 0;
  bool closed_ = false;
};

}  // namespace rangekit
