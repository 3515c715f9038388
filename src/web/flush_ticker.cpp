#include "web/flush_ticker.hpp"

#include "web/event_stream.hpp"

namespace rangekit::web {

FlushTicker::FlushTicker(net::io_context& context, std::shared_ptr<Poster> poster, std::chrono::milliseconds tick)
    : poster_(std::move(poster)), tick_(tick), timer_(context) {}

void FlushTicker::request(std::function<void()> flush) {
  {
    std::lock_guard lock(mutex_);
    pending_.push_back(std::move(flush));
    if (armed_) return;
    armed_ = true;
  }
  // Once the server stops, the poster drops this and nothing runs again.
  poster_->post([self = shared_from_this()] {
    self->timer_.expires_after(self->tick_);
    self->timer_.async_wait([self](beast::error_code error) {
      if (!error) self->fire();
    });
  });
}

void FlushTicker::fire() {
  {
    std::lock_guard lock(mutex_);
    running_.swap(pending_);
    armed_ = false;  // a request from now on starts the next tick
  }
  for (auto& flush : running_) flush();
  running_.clear();
}

}  // namespace rangekit::web
