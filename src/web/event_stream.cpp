#include "web/event_stream.hpp"

#include <cmath>
#include <variant>

#include "rangekit/record/format.hpp"
#include "web/flush_ticker.hpp"
#include "web/json_views.hpp"

namespace rangekit::web {
namespace {

// The one number a live view plots for a sample, and its unit; none for
// look-down edges, device errors and LS5 no-signal records (drawn as gaps).
std::optional<std::pair<double, const char*>> plotted(const Sample& sample) {
  if (sample.distance_m) return std::pair{*sample.distance_m, "m"};
  if (!sample.targets.empty()) return std::pair{sample.targets.front().distance_m, "m"};
  if (sample.distance_mm) return std::pair{*sample.distance_mm, "mm"};
  if (sample.derivative_mm) return std::pair{*sample.derivative_mm, "mm"};
  return std::nullopt;
}

std::string number_text(double value) {
  std::array<char, 32> buffer{};
  std::snprintf(buffer.data(), buffer.size(), "%.6g", value);
  return buffer.data();
}

}  // namespace

template <class Stream>
struct EventStream<Stream>::Aggregate {
  std::int64_t bucket = -1;
  std::uint64_t last_id = 0;
  std::size_t count = 0;    // samples in the bucket
  std::size_t without = 0;  // of which with no plotted value (gaps)
  double min = 0;
  double max = 0;
  double last = 0;
  const char* unit = "";
  std::chrono::system_clock::time_point time;
};

template <class Stream>
EventStream<Stream>::EventStream(Stream stream, hub::SubscriptionPtr subscription, std::vector<hub::HubItemPtr> backlog,
                                 std::uint64_t after, EventStreamOptions options, std::shared_ptr<FlushTicker> ticker,
                                 EventStreamCounters& counters, EventCache& cache)
    : stream_(std::move(stream)),
      subscription_(std::move(subscription)),
      backlog_(std::move(backlog)),
      last_sent_(after),
      options_(options),
      ticker_(std::move(ticker)),
      counters_(counters),
      cache_(cache),
      keepalive_(tcp_of(stream_).get_executor()),
      bucket_timer_(tcp_of(stream_).get_executor()) {
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
  // A bounded kernel buffer per client: a client that stops reading fills it and then its
  // queue, and is cut off, instead of the system holding megabytes for it.
  beast::error_code ignored;
  tcp_of(stream_).socket().set_option(net::socket_base::send_buffer_size(64 * 1024), ignored);
  arm_keepalive();
  if (options_.max_rate) arm_bucket_timer();
  write(std::move(out));
}

template <class Stream>
void EventStream<Stream>::append(std::string& out, const hub::HubItem& item) {
  if (item.sequence <= last_sent_) return;  // already sent from the backlog
  last_sent_ = item.sequence;
  const auto* sample = std::get_if<Sample>(&item.item);
  if (options_.max_rate && sample != nullptr) {
    auto& slot = aggregates_[item.sensor];
    if (!slot) slot = std::make_unique<Aggregate>();
    Aggregate& aggregate = *slot;
    const double period_ms = 1000.0 / *options_.max_rate;
    const auto now = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch());
    const auto bucket = static_cast<std::int64_t>(std::floor(now.count() / period_ms));
    if (aggregate.count > 0 && bucket != aggregate.bucket) append_aggregates(out, true);
    aggregate.bucket = bucket;
    aggregate.last_id = item.sequence;
    aggregate.time = sample->time;
    ++aggregate.count;
    if (const auto value = plotted(*sample)) {
      const std::size_t valued = aggregate.count - aggregate.without;
      aggregate.min = valued == 1 ? value->first : std::min(aggregate.min, value->first);
      aggregate.max = valued == 1 ? value->first : std::max(aggregate.max, value->first);
      aggregate.last = value->first;
      aggregate.unit = value->second;
    } else {
      ++aggregate.without;
    }
    return;
  }
  if (options_.max_rate) append_aggregates(out, true);  // a link event after the samples before it
  out += cache_.frame(item);
}

template <class Stream>
void EventStream<Stream>::append_aggregates(std::string& out, bool all) {
  const double period_ms = options_.max_rate ? 1000.0 / *options_.max_rate : 0;
  const auto now = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch());
  const auto current = period_ms > 0 ? static_cast<std::int64_t>(std::floor(now.count() / period_ms)) : 0;
  for (auto& [sensor, slot] : aggregates_) {
    Aggregate& aggregate = *slot;
    if (aggregate.count == 0 || (!all && aggregate.bucket >= current)) continue;
    std::string time;
    record::append_iso_time(time, aggregate.time);
    const bool valued = aggregate.count > aggregate.without;
    const std::string id = std::to_string(aggregate.last_id);
    out += "id: ";
    out += id;
    out += "\nevent: aggregate\ndata: {\"id\":";
    out += id;
    out += ",\"sensor\":\"";
    out += sensor;
    out += "\",\"type\":\"aggregate\",\"data\":{\"time\":\"";
    out += time;
    out += "\",\"count\":";
    out += std::to_string(aggregate.count);
    out += ",\"gaps\":";
    out += std::to_string(aggregate.without);
    if (valued) {
      out += ",\"min\":" + number_text(aggregate.min) + ",\"max\":" + number_text(aggregate.max) +
             ",\"last\":" + number_text(aggregate.last) + ",\"unit\":\"" + aggregate.unit + "\"";
    }
    out += "}}\n\n";
    aggregate = Aggregate{};
  }
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
  for (;;) {
    const auto items = subscription_->take(1024, std::chrono::milliseconds(0));
    for (const hub::HubItemPtr& item : items) append(out, *item);
    if (!out.empty() || items.empty()) break;
  }
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
  bucket_timer_.cancel();
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
void EventStream<Stream>::arm_bucket_timer() {
  bucket_timer_.expires_after(std::chrono::microseconds(static_cast<std::int64_t>(1e6 / *options_.max_rate)));
  bucket_timer_.async_wait([weak = this->weak_from_this()](beast::error_code error) {
    auto self = weak.lock();
    if (error || !self || self->finished_) return;
    if (!self->writing_) {
      std::string out;
      self->append_aggregates(out, false);  // buckets that ended without a newer sample
      if (!out.empty()) self->write(std::move(out));
    }
    self->arm_bucket_timer();
  });
}

template class EventStream<PlainStream>;
template class EventStream<TlsStream>;

}  // namespace rangekit::web
