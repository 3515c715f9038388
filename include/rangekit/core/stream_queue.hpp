// A bounded hand-off between a reader thread and a consumer. The reader never
// waits on the consumer: when the queue is full the oldest item is dropped and
// counted, so a slow consumer loses records visibly instead of stalling the port.
#pragma once

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
  explicit StreamQueue(std::size_t capacity = 65536) : capacity_(capacity == 0 ? 1 : capacity) {}

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
    }
    ready_.notify_one();
  }

  // Waits up to `timeout` for an item; nullopt on timeout or once closed and empty.
  std::optional<T> pop(std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    ready_.wait_for(lock, timeout, [this] { return !items_.empty() || closed_; });
    if (items_.empty()) return std::nullopt;
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
  std::uint64_t dropped_ = 0;
  bool closed_ = false;
};

}  // namespace rangekit
