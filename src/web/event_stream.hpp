// One Server-Sent Events client: the backlog from the ring after Last-Event-ID,
// then every live item of its subscription, written as fast as the client reads.
// A client that falls stream_queue items behind is cut off (counted); its
// EventSource reconnects and resumes from the ring. With max_rate the samples of
// each sensor are merged into min/max/last (web/sample_aggregate.hpp; link events pass
// unmerged), at most max_rate a second, so a 1 kHz sensor stays cheap for a browser. A
// sensor's merge goes out once 1/max_rate s has passed since its previous one: a burst (an
// LS5 UDP packet, 168 readings at once) is shown as it comes, not a slot later.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rangekit/hub/fanout.hpp"
#include "web/event_cache.hpp"
#include "web/http.hpp"
#include "web/sample_aggregate.hpp"

namespace rangekit::web {

class Poster;
class FlushTicker;

struct EventStreamOptions {
  std::optional<double> max_rate;  // points a second per sensor, 1-1000
  std::chrono::seconds keepalive{15};
};

struct EventStreamCounters {
  std::atomic<std::uint64_t> open{0};
  std::atomic<std::uint64_t> cut_off{0};
};

// Where a stream starts: after `after`, with the items kept since then. A resume that could not
// be honoured in full (items no longer kept, or an id of an earlier run of the service) says
// why in `gap`, which the client receives first as `event: resume`.
struct StreamStart {
  std::uint64_t after = 0;
  std::vector<hub::HubItemPtr> backlog;
  std::string gap;
};

template <class Stream>  // PlainStream or TlsStream (instantiated in event_stream.cpp)
class EventStream : public std::enable_shared_from_this<EventStream<Stream>> {
 public:
  EventStream(Stream stream, hub::SubscriptionPtr subscription, StreamStart start, EventStreamOptions options,
              std::shared_ptr<FlushTicker> ticker, EventStreamCounters& counters, EventCache& cache);
  ~EventStream();
  void start();

 private:
  void flush();
  void append(std::string& out, const hub::HubItem& item);
  // The merges that are due (all: every one with samples, before a link event).
  void append_aggregates(std::string& out, bool all);
  // A sensor's merge; items come in runs of one sensor, so it is looked up once a run.
  struct Merge {
    SampleAggregate aggregate;
    std::chrono::steady_clock::time_point last_sent;
  };
  Merge& merge_of(const std::string& sensor);
  void write(std::string text);
  void finish();
  void arm_keepalive();
  void arm_merge_timer();

  Stream stream_;
  hub::SubscriptionPtr subscription_;
  std::vector<hub::HubItemPtr> backlog_;
  std::string gap_;
  std::uint64_t last_sent_;
  EventStreamOptions options_;
  std::shared_ptr<FlushTicker> ticker_;
  EventStreamCounters& counters_;
  EventCache& cache_;
  net::steady_timer keepalive_;
  net::steady_timer merge_timer_;
  std::shared_ptr<std::atomic<bool>> wake_pending_ = std::make_shared<std::atomic<bool>>(false);
  std::map<std::string, Merge, std::less<>> merges_;
  const std::string* run_sensor_ = nullptr;  // the key of run_merge_ in merges_
  Merge* run_merge_ = nullptr;
  std::vector<std::pair<const std::string*, Merge*>> holding_;  // the merges with samples, each once
  std::chrono::steady_clock::duration period_{};                // 1/max_rate
  std::string pending_;                                         // what is being written
  bool writing_ = false;
  bool finished_ = false;
};

// Posts work onto the event loop from other threads (the hub's workers, the
// command pool) for as long as the server runs; a no-op once it stops.
class Poster {
 public:
  explicit Poster(net::io_context& context) : context_(&context) {}
  template <class F>
  void post(F&& work) {
    std::lock_guard lock(mutex_);
    if (context_ != nullptr) net::post(*context_, std::forward<F>(work));
  }
  void shut() {
    std::lock_guard lock(mutex_);
    context_ = nullptr;
  }

 private:
  std::mutex mutex_;
  net::io_context* context_;
};

}  // namespace rangekit::web
