// An SSE client of `rangekit serve` for the service benches: reads a stream on its own thread,
// counts its sample and aggregate events, and keeps, with the time it arrived, what the
// bench's `note` makes of each event (a code and a sensor, to match it with what was sent).
#pragma once

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "web/http_client.hpp"

namespace rangekit::bench {

template <class Noted>
class SseReader {
 public:
  using Clock = std::chrono::steady_clock;
  // What to keep of one event's block ("event: ...\ndata: {...}"); nullopt: nothing.
  using Note = std::function<std::optional<Noted>(std::string_view block)>;
  struct Arrival {
    Noted what;
    Clock::time_point at;
  };

  SseReader(std::uint16_t port, const std::string& target, Note note) : note_(std::move(note)) {
    fd_ = web_test::connect_to(port);
    if (fd_ >= 0) web_test::send_all(fd_, web_test::request_text("GET", target, {}, {}, port));
    thread_ = std::thread([this] { run(); });
  }
  ~SseReader() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    if (fd_ >= 0) ::close(fd_);
  }
  SseReader(const SseReader&) = delete;
  SseReader& operator=(const SseReader&) = delete;

  [[nodiscard]] std::uint64_t events() const { return events_; }
  std::vector<Arrival> arrivals() {
    const std::lock_guard lock(mutex_);
    return arrivals_;
  }

 private:
  void run() {
    std::string buffer;
    while (!stop_ && fd_ >= 0) {
      if (!web_test::read_some(fd_, buffer, std::chrono::milliseconds(50))) return;
      const auto now = Clock::now();
      std::size_t start = 0;
      for (auto end = buffer.find("\n\n"); end != std::string::npos; end = buffer.find("\n\n", start)) {
        const std::string_view block(buffer.data() + start, end - start);
        start = end + 2;
        if (block.find("event: sample") == std::string_view::npos &&
            block.find("event: aggregate") == std::string_view::npos)
          continue;
        ++events_;
        if (auto noted = note_(block)) {
          const std::lock_guard lock(mutex_);
          arrivals_.push_back({std::move(*noted), now});
        }
      }
      buffer.erase(0, start);
    }
  }

  Note note_;
  int fd_ = -1;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> events_{0};
  std::mutex mutex_;
  std::vector<Arrival> arrivals_;
};

}  // namespace rangekit::bench
