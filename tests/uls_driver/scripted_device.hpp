// A scripted ULS on the far end of an in-memory loopback pair: a thread reads
// request lines (up to CR) and answers each with the bytes a handler returns;
// tests can also inject bytes at any moment. Records every request it saw.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "rangekit/core/loopback.hpp"

namespace rangekit::uls::testing {

class ScriptedDevice {
 public:
  // Gets a request line without its CR; returns the bytes to send back ("" = silence).
  using Handler = std::function<std::string(const std::string& request)>;

  ScriptedDevice(TransportPtr device_end, Handler handler)
      : end_(std::move(device_end)), handler_(std::move(handler)), thread_([this] { run(); }) {}
  ~ScriptedDevice() {
    stop_ = true;
    thread_.join();
  }
  ScriptedDevice(const ScriptedDevice&) = delete;
  ScriptedDevice& operator=(const ScriptedDevice&) = delete;

  void send(const std::string& bytes) {
    std::lock_guard lock(write_mutex_);
    if (end_) (void)end_->write_all(as_bytes(bytes));
  }
  // Closes the device end: the driver sees the link go away.
  void unplug() {
    std::lock_guard lock(write_mutex_);
    if (end_) end_->close();
  }
  std::vector<std::string> requests() {
    std::lock_guard lock(mutex_);
    return requests_;
  }
  // Waits until `count` requests arrived (or 10 s).
  bool wait_for_requests(std::size_t count) {
    std::unique_lock lock(mutex_);
    return seen_.wait_for(lock, std::chrono::seconds(10), [&] { return requests_.size() >= count; });
  }

 private:
  void run() {
    std::string line;
    std::uint8_t buffer[256];
    while (!stop_) {
      auto got = end_->read_some(buffer, std::chrono::milliseconds(20));
      if (!got) {
        if (got.error().code == Errc::timeout) continue;
        return;  // closed
      }
      for (std::size_t i = 0; i < *got; ++i) {
        if (buffer[i] != '\r') {
          line.push_back(static_cast<char>(buffer[i]));
          continue;
        }
        // Recorded before the handler runs: a handler may send (GO's lines) and the driver
        // can act on those bytes before this thread gets here again.
        {
          std::lock_guard lock(mutex_);
          requests_.push_back(line);
        }
        seen_.notify_all();
        const std::string reply = handler_(line);
        if (!reply.empty()) send(reply);
        line.clear();
      }
    }
  }

  TransportPtr end_;
  Handler handler_;
  std::mutex mutex_;
  std::mutex write_mutex_;
  std::condition_variable seen_;
  std::vector<std::string> requests_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace rangekit::uls::testing
