// One timer for the wake-ups of every SSE stream of a server. A 1 kHz sensor watched
// by ten clients used to wake the event loop ten times per record, each stream with its
// own timer and its own small write; gathered into one tick, the loop wakes once per
// tick and each client gets one write holding everything since the last.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "web/http.hpp"

namespace rangekit::web {

class Poster;

class FlushTicker : public std::enable_shared_from_this<FlushTicker> {
 public:
  // `tick`: how long the first request of a tick waits for others to join it; the
  // latency it adds is at most that, well inside the 20 ms goal of docs/service.md.
  FlushTicker(net::io_context& context, std::shared_ptr<Poster> poster, std::chrono::milliseconds tick);

  // From any thread: runs `flush` on the event loop at the end of the current tick.
  void request(std::function<void()> flush);

 private:
  void fire();

  std::shared_ptr<Poster> poster_;
  std::chrono::milliseconds tick_;
  net::steady_timer timer_;  // touched only on the event loop
  std::mutex mutex_;
  std::vector<std::function<void()>> pending_;
  std::vector<std::function<void()>> running_;  // kept between ticks: no allocation once warm
  bool armed_ = false;
};

}  // namespace rangekit::web
