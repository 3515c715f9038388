#include "web/event_stream.hpp"

#include <variant>

#include "web/flush_ticker.hpp"
#include "web/json_views.hpp"
#include "web/sample_aggregate.hpp"

namespace rangekit::web {
namespace {

constexpr std::size_t take_batch = 1024;
constexpr std::size_t flush_text_limit = std::size_t{64} * 1024;

}  // namespace

template <class Stream>
EventStream<Stream>::EventStream(Stream stream, hub::SubscriptionPtr subscription, StreamStart start,
                                 EventStreamOptions options, std::shared_ptr<FlushTicker> ticker,
                                 EventStreamCounters& counters, EventCache& cache)
    : stream_(std::move(stream)),
      subscription_(std::move(subscription)),
      backlog_(std::move(start.backlog)),
      gap_(std::move(start.gap)),
      last_sent_(start.after),
      options_(options),
      ticker_(std::move(ticker)),
      counters_(counters),
      cache_(cache),
      keepalive_(tcp_of(stream_).get_executor()),
      merge_timer_(tcp_of(stream_).get_executor()) {
  ++counters_.open;
}

template <class Stream>
EventStream<Stream>::~EventStream() {
  --counters_.open;
  subscription_->close();
}

template <class Stream>
void EventStream<Stream>::start() {
  std::string out =
      "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-cache\r\n"
      "X-Accel-Buffering: no\r\nConnection: keep-alive\r\n\r\n: rangekit\n\n";
  // No id: the client's Last-Event-ID stays that of the last item it has.
  if (!gap_.empty()) {
    out += "event: resume\ndata: " + nlohmann::json{{"complete", false}, {"message", gap_}}.dump() + "\n\n";
  }
  for (const hub::HubItemPtr& item : backlog_) append(out, *item);
  backlog_.clear();
  // The listener is called on a hub worker: it only asks the server's ticker for a flush,
  // once until that flush runs, so that a 1 kHz sensor wakes the loop for batches, not
  // records, and all streams share the wake-up.
  std::weak_ptr<EventStream> weak = this->weak_from_this();
  subscription_->set_listener([weak, ticker = ticker_, wake = wake_pending_] {
    if (wake->exchange(true)) return;
    ticker->request([weak] {
      auto self = weak.lock();
      if (!self) return;
      self->wake_pending_->store(false);  // before taking: an item landing after the take asks again
      self->flush();
    });
  });
  tcp_of(stream_).expires_never();
  bound_send_buffer(tcp_of(stream_));  // a client that stops reading fills it, then its queue, and is cut off
  arm_keepalive();
  if (options_.max_rate) {
    period_ = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(1.0 / *options_.max_rate));
    arm_merge_timer();
  }
  write(std::move(out));
}

template <class Stream>
void EventStream<Stream>::append(std::string& out, const hub::HubItem& item) {
  if (item.sequence <= last_sent_) return;  // already sent from the backlog
  last_sent_ = item.sequence;
  const auto* sample = std::get_if<Sample>(&item.item);
  if (options_.max_rate && sample != nullptr) {
    Merge& merge = merge_of(item.sensor);
    if (merge.aggregate.empty()) holding_.emplace_back(run_sensor_, &merge);
    merge.aggregate.add(*sample, item.sequence);
    return;
  }
  if (options_.max_rate) append_aggregates(out, true);  // a link event after the samples before it
  out += cache_.frame(item);
}

template <class Stream>
typename EventStream<Stream>::Merge& EventStream<Stream>::merge_of(const std::string& sensor) {
  if (run_sensor_ == nullptr || *run_sensor_ != sensor) {
    const auto found = merges_.try_emplace(sensor).first;
    run_sensor_ = &found->first;
    run_merge_ = &found->second;
  }
  return *run_merge_;
}

template <class Stream>
void EventStream<Stream>::append_aggregates(std::string& out, bool all) {
  const auto now = std::chrono::steady_clock::now();
  // Only the merges holding samples are looked at: a site has a hundred sensors, a flush a few.
  std::erase_if(holding_, [&](const std::pair<const std::string*, Merge*>& held) {
    Merge& merge = *held.second;
    if (!all && now - merge.last_sent < period_) return false;
    merge.aggregate.append_event(out, *held.first);
    merge.last_sent = now;
    return true;
  });
}

template <class Stream>
void EventStream<Stream>::flush() {
  if (finished_) return;
  // Fell stream_queue items behind: closed now, even with a write still pending (the
  // client stopped reading; that write would never end).
  if (subscription_->cut_off()) return finish();
  if (writing_) return;
  std::string out;
  // Merged samples may leave nothing to write yet: take on until there is, or the queue is empty
  // (the listener speaks again only when an item lands in an empty queue).
  // What is queued is taken whole (up to 64 KiB of text), so that a burst of one sensor is
  // merged into one event, not cut at a batch's end.
  for (;;) {
    const auto items = subscription_->take(take_batch, std::chrono::milliseconds(0));
    for (const hub::HubItemPtr& item : items) append(out, *item);
    if (items.size() < take_batch || out.size() >= flush_text_limit) break;
  }
  if (options_.max_rate) append_aggregates(out, false);
  if (out.empty()) {
    if (subscription_->closed()) finish();
    return;
  }
  write(std::move(out));
}

template <class Stream>
void EventStream<Stream>::write(std::string text) {
  writing_ = true;
  pending_ = std::move(text);
  net::async_write(stream_, net::buffer(pending_),
                   [self = this->shared_from_this()](beast::error_code error, std::size_t /*bytes*/) {
                     self->writing_ = false;
                     if (error) {
                       self->finish();  // the client went away
                       return;
                     }
                     self->flush();
                   });
}

template <class Stream>
void EventStream<Stream>::finish() {
  if (finished_) return;
  finished_ = true;
  if (subscription_->cut_off()) ++counters_.cut_off;
  subscription_->close();
  keepalive_.cancel();
  merge_timer_.cancel();
  beast::error_code ignored;
  tcp_of(stream_).socket().shutdown(tcp::socket::shutdown_both, ignored);
  tcp_of(stream_).socket().close(ignored);
}

template <class Stream>
void EventStream<Stream>::arm_keepalive() {
  keepalive_.expires_after(options_.keepalive);
  // The timer holds the stream alive while it is open: nothing else does between two writes.
  keepalive_.async_wait([self = this->shared_from_this()](beast::error_code error) {
    if (error || self->finished_) return;
    // A comment line: keeps proxies from closing an idle stream and finds clients that left.
    if (!self->writing_) self->write(": keepalive\n\n");
    self->arm_keepalive();
  });
}

template <class Stream>
void EventStream<Stream>::arm_merge_timer() {
  merge_timer_.expires_after(period_);
  merge_timer_.async_wait([weak = this->weak_from_this()](beast::error_code error) {
    auto self = weak.lock();
    if (error || !self || self->finished_) return;
    if (!self->writing_) {
      std::string out;
      self->append_aggregates(out, false);  // merges that fell due without a newer sample
      if (!out.empty()) self->write(std::move(out));
    }
    self->arm_merge_timer();
  });
}

template class EventStream<PlainStream>;
template class EventStream<TlsStream>;

}  // namespace rangekit::web
