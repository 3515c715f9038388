// A bounded hand-off between a reader thread and a consumer. The reader never waits on
// the consumer: when full, the oldest item is dropped and counted, so a slow consumer
// loses records visibly instead of stalling the port.
#pragma once

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

namespace rangekit {

// With a gather time, a consumer that found the queue empty is woken by the first item
// and lets the next ones collect for that long: one wake-up per batch, for at most that
// much latency.
//
// Items live in one vector under the mutex; every access to it, to `head_` and to the
// flags holds the mutex, so the queue is race-free by construction. take_all() swaps that
// vector with the consumer's (empty) one under the lock: the consumer gets the batch in
// O(1) and the reader gets the consumer's storage back, so after warm-up neither side
// allocates per item (a deque would allocate a node for every item or two). The consumer's
// vector is touched outside the lock only by the consumer.
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
      if (queued() >= capacity_) {
        ++head_;  // the oldest is lost; its slot goes at the next compaction
        ++dropped_;
        compact();
      }
      items_.push_back(std::move(item));
      // Consumers wait only for an empty queue to fill (or for the end of a gather):
      // the pushes after the first find nobody to wake.
      if (queued() > 1) return;
    }
    ready_.notify_all();
  }

  // Pushes every item of `batch` in order under one lock and with at most one wake-up
  // (a reader handing over what one read decoded); `batch` is left empty with its storage.
  void push_all(std::vector<T>& batch) {
    if (batch.empty()) return;
    bool was_empty = false;
    {
      std::lock_guard lock(mutex_);
      if (!closed_) {
        was_empty = queued() == 0;
        for (T& item : batch) {
          if (queued() >= capacity_) {
            ++head_;
            ++dropped_;
            compact();
          }
          items_.push_back(std::move(item));
        }
      }
    }
    batch.clear();
    if (was_empty) ready_.notify_all();
  }

  // Waits up to `timeout` for an item; nullopt on timeout or once closed and empty.
  std::optional<T> pop(std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    if (!wait_for_items(lock, timeout)) return std::nullopt;
    T item = std::move(items_[head_]);
    ++head_;
    compact();
    return item;
  }

  // Waits up to `timeout` as pop() does, then moves everything queued into `batch`,
  // oldest first, replacing what it held. False (and `batch` empty) on timeout or once
  // closed and empty. Pass the same vector each time: its storage is reused.
  bool take_all(std::vector<T>& batch, std::chrono::milliseconds timeout) {
    batch.clear();  // the consumer's own vector: destroyed outside the lock
    std::unique_lock lock(mutex_);
    if (!wait_for_items(lock, timeout)) return false;
    if (head_ == 0) {
      batch.swap(items_);  // the reader keeps pushing into the consumer's old storage
    } else {
      batch.insert(batch.end(), std::make_move_iterator(items_.begin() + static_cast<std::ptrdiff_t>(head_)),
                   std::make_move_iterator(items_.end()));
      items_.clear();
      head_ = 0;
    }
    return true;
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
    head_ = 0;
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
    return queued();
  }

 private:
  // All below: with the mutex held.
  [[nodiscard]] std::size_t queued() const { return items_.size() - head_; }

  // Waits for an item, then (with a gather time) for the next ones to join it.
  bool wait_for_items(std::unique_lock<std::mutex>& lock, std::chrono::milliseconds timeout) {
    // A condition wait with an expired deadline still sleeps in the kernel: a zero timeout
    // (a consumer draining what is there) only looks.
    if (timeout.count() <= 0) return queued() > 0;
    const auto deadline = std::chrono::steady_clock::now() + std::min(timeout, std::chrono::milliseconds(86'400'000));
    while (queued() == 0) {
      if (!ready_.wait_until(lock, deadline, [this] { return queued() > 0 || closed_; })) return false;
      if (queued() == 0) return false;  // closed and drained
      // Woken for one item: let the next ones join it (a close ends the wait). Another
      // consumer may take it meanwhile; then this one waits on.
      if (gather_.count() > 0) ready_.wait_for(lock, gather_, [this] { return closed_ || queued() == 0; });
    }
    return true;
  }

  // Items before head_ have been taken or dropped. Reset when all are, else erase them
  // once they are at least half the vector: each element moves O(1) times on average.
  void compact() {
    if (head_ == items_.size()) {
      items_.clear();
      head_ = 0;
    } else if (head_ >= 64 && head_ * 2 >= items_.size()) {
      items_.erase(items_.begin(), items_.begin() + static_cast<std::ptrdiff_t>(head_));
      head_ = 0;
    }
  }

  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::vector<T> items_;  // queued: [head_, size())
  std::size_t head_ = 0;
  std::size_t capacity_;
  std::chrono::microseconds gather_;
  std::uint64_t dropped_ = 0;
  bool closed_ = false;
};

}  // namespace rangekit
