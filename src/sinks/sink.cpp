// Two threads per sink: the intake takes the hub's items into the spool (so a slow or absent
// historian never holds the hub's queue), the drain sends the spool oldest first and removes
// only what the historian confirmed.
#include "rangekit/sinks/sink.hpp"

#include <algorithm>
#include <cctype>
#include <condition_variable>
#include <filesystem>
#include <future>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "rangekit/hub/sink_url.hpp"
#include "sinks/reading_rows.hpp"
#include "sinks/writer.hpp"

namespace rangekit::sinks {

using Clock = std::chrono::steady_clock;

// The hub's news for the intake. Shared with the subscriptions' listeners, which the hub may
// still be calling a moment after the sink is gone.
struct ItemsSignal {
  std::mutex mutex;
  std::condition_variable wake;
  bool ready = false;
  bool stopping = false;
};

struct Sink::Impl {
  SinkOptions options;
  const SinkKind* kind = nullptr;
  std::unique_ptr<Writer> writer;
  std::string spool_path;
  std::unique_ptr<Spool> spool;
  std::vector<hub::SubscriptionPtr> subscriptions;
  std::shared_ptr<ItemsSignal> items = std::make_shared<ItemsSignal>();

  std::mutex mutex;  // guards the flags and counters below
  std::condition_variable wake;
  bool stopping = false;
  bool rows_ready = true;  // rows of an earlier run may wait
  bool up = false;
  std::string error;
  std::uint64_t written = 0;
  std::uint64_t rejected = 0;
  std::uint64_t failures = 0;
  std::uint64_t spool_dropped = 0;
  bool told_full = false;  // the spool's cap is logged once

  // The drain thread's batches between two writes. A batch that filled its limit (a backlog)
  // has the next one read while it is written, and leaves the spool while that next one is.
  std::optional<std::vector<SpoolRow>> ahead;  // read after the last batch written
  std::vector<SpoolRow> unremoved;             // confirmed (or refused), still in the spool

  std::thread intake;
  std::thread drain;

  Impl() = default;
  ~Impl() {
    for (const hub::SubscriptionPtr& subscription : subscriptions) subscription->close();
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  void log(const std::string& line) const {
    if (options.log) options.log("sink " + hub::redacted_url(options.config.url) + ": " + line);
  }
  // Waits until `until`, or until stopping; true when stopping.
  bool wait_stopping(Clock::time_point until) {
    std::unique_lock lock(mutex);
    return wake.wait_until(lock, until, [&] { return stopping; });
  }

  void run_intake();
  // Takes what the hub queued into the spool; `closing`: every open window too (at stop).
  void take_once(ReadingRows& rows, std::chrono::milliseconds wait, bool closing);
  void run_drain();
  // A batch is at most what drain_rate allows in one batch_time, so the pace holds within a second too.
  [[nodiscard]] std::size_t batch_limit() const {
    const auto per_batch = static_cast<std::size_t>(static_cast<double>(options.config.drain_rate) *
                                                    std::chrono::duration<double>(options.batch_time).count());
    return std::clamp<std::size_t>(per_batch, 1, options.batch_rows);
  }
  // One write of the oldest rows: how many the historian confirmed or refused (0: none
  // waited), none when the write failed and waits to be retried.
  std::optional<std::size_t> drain_once(std::chrono::milliseconds& backoff);
  // Removes `unremoved` now; false (the error kept) when the spool failed, and then every row
  // still in it is read again from the oldest.
  bool remove_unremoved();
  SinkStats stats();
};

std::string spool_file_name(const hub::SinkConfig& config) {
  std::string name = config.kind + "-";
  // Without a password, so that none is on disk and a new password keeps the same spool.
  const std::string shown = hub::redacted_url(config.url);
  std::string_view url = shown;
  if (const auto scheme = url.find("://"); scheme != std::string_view::npos) url.remove_prefix(scheme + 3);
  std::string named(url);
  // Two tables of one database: two spools (the default table's is named after the URL alone).
  if (config.kind == "postgres" && config.table != "readings") named += "/" + config.table;
  for (const char c : named) {
    const bool plain = std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '.' || c == '_';
    if (plain) {
      name += c;
    } else if (name.back() != '-') {
      name += '-';
    }
  }
  while (name.back() == '-') name.pop_back();
  return name + ".spool";
}

void Sink::Impl::take_once(ReadingRows& rows, std::chrono::milliseconds wait, bool closing) {
  {
    std::unique_lock lock(items->mutex);
    items->wake.wait_for(lock, wait, [&] { return items->ready || items->stopping; });
    items->ready = false;
  }
  std::vector<SpoolRow> batch;
  for (const hub::SubscriptionPtr& subscription : subscriptions) {
    for (const hub::HubItemPtr& item : subscription->take(options.batch_rows, std::chrono::milliseconds(0))) {
      rows.add(*item, *spool, batch);
    }
  }
  if (closing) {
    rows.close_all(*spool, batch);
  } else {
    rows.close_windows(std::chrono::system_clock::now(), *spool, batch);
  }
  if (batch.empty()) return;
  auto dropped = spool->append(batch);
  const std::lock_guard lock(mutex);
  if (!dropped) {
    error = dropped.error().message;  // the rows are lost: the disk refused them
    spool_dropped += batch.size();
    log(error);
    return;
  }
  spool_dropped += *dropped;
  if (*dropped > 0 && !told_full) {
    told_full = true;
    log("spool above spool_max_mb = " + std::to_string(options.config.spool_max_mb) +
        ": dropping the oldest readings (counted in dropped)");
  }
  rows_ready = true;
  wake.notify_all();
}

void Sink::Impl::run_intake() {
  ReadingRows rows(options.config.max_rate_hz, kind->encode);
  for (;;) {
    take_once(rows, options.batch_time, false);
    // Readings gathered for a while go to disk in one transaction, not one each (1 kHz sensors).
    std::unique_lock lock(items->mutex);
    if (items->wake.wait_for(lock, options.intake_gather, [&] { return items->stopping; })) break;
  }
  // What the hub queued until now goes to the spool too, for the next start.
  for (const hub::SubscriptionPtr& subscription : subscriptions) subscription->close();
  take_once(rows, std::chrono::milliseconds(0), true);
}

bool Sink::Impl::remove_unremoved() {
  if (unremoved.empty()) return true;
  auto removed = spool->remove(unremoved);
  unremoved.clear();
  if (removed) return true;
  ahead.reset();
  const std::lock_guard lock(mutex);
  error = removed.error().message;
  return false;
}

std::optional<std::size_t> Sink::Impl::drain_once(std::chrono::milliseconds& backoff) {
  std::vector<SpoolRow> rows;
  if (ahead) {
    rows = std::move(*ahead);
    ahead.reset();
  } else {
    auto read = spool->oldest(batch_limit(), unremoved.empty() ? 0 : unremoved.back().id);
    if (read) rows = std::move(*read);
    if (!read || rows.empty()) {
      const bool removed = remove_unremoved();
      const std::lock_guard lock(mutex);
      if (!read) error = read.error().message;
      rows_ready = false;
      return removed ? std::optional<std::size_t>(0) : std::nullopt;
    }
  }
  // While the historian takes this batch, on another thread: the batch before leaves the spool
  // and, behind a full batch, the next is read. A row still leaves only after its confirmation.
  struct Overlap {
    Status removed = ok_status();
    std::optional<Result<std::vector<SpoolRow>>> next;
  };
  std::future<Overlap> overlap;
  bool full = rows.size() >= batch_limit();
  {
    const std::lock_guard lock(mutex);
    full = full && up;  // not while the historian is away: a failed write would discard it
  }
  if (full || !unremoved.empty()) {
    overlap =
        std::async(std::launch::async, [this, confirmed = std::move(unremoved), after = full ? rows.back().id : 0] {
          Overlap done;
          done.removed = spool->remove(confirmed);
          if (after > 0) done.next = spool->oldest(batch_limit(), after);
          return done;
        });
    unremoved.clear();
  }
  const WriteOutcome outcome = writer->write(rows);
  std::optional<Overlap> overlapped;
  if (overlap.valid()) overlapped = overlap.get();
  if (overlapped && !overlapped->removed) {
    const std::lock_guard lock(mutex);
    error = overlapped->removed.error().message;  // those rows are read again, with this batch
    return std::nullopt;
  }
  const bool confirmed = outcome.kind == WriteOutcome::Kind::confirmed;
  const bool refused = outcome.kind == WriteOutcome::Kind::refused;
  const std::size_t count = rows.size();
  if (confirmed || refused) {
    if (overlapped && overlapped->next && *overlapped->next && !(*overlapped->next)->empty()) {
      ahead = std::move(**overlapped->next);
      unremoved = std::move(rows);  // removed while `ahead` is written, or before the drain waits
    } else {
      unremoved = std::move(rows);
      if (!remove_unremoved()) return std::nullopt;
    }
  }
  const std::lock_guard lock(mutex);
  if (confirmed) {
    if (!up) log(written == 0 && failures == 0 ? "up" : "up again, sending the spooled readings");
    up = true;
    error.clear();
    written += count;
    backoff = options.backoff_min;
    return count;
  }
  if (refused) {
    rejected += count;
    log("refused " + std::to_string(count) + " rows (" + outcome.why + ")");
    return count;
  }
  ++failures;
  if (up || error.empty()) log("down (" + outcome.why + "): readings wait in the spool");
  up = false;
  error = outcome.why;
  return std::nullopt;
}

void Sink::Impl::run_drain() {
  std::chrono::milliseconds backoff = options.backoff_min;
  // Before any wait, rows confirmed but kept to be removed beside the next write leave the
  // spool now; true when stopping.
  const auto wait_for_pace = [&](Clock::time_point until) {
    if (Clock::now() < until) remove_unremoved();
    return wait_stopping(until);
  };
  for (;;) {
    {
      std::unique_lock lock(mutex);
      wake.wait_for(lock, options.batch_time, [&] { return rows_ready || stopping; });
      if (stopping) break;
    }
    const auto started = Clock::now();
    const auto sent = drain_once(backoff);
    if (!sent) {
      if (wait_for_pace(Clock::now() + backoff)) break;
      backoff = std::min(backoff * 2, options.backoff_max);
      continue;
    }
    if (*sent == 0) continue;
    // At most drain_rate rows a second, so a long backlog does not starve the historian's other writers.
    auto pace = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(static_cast<double>(*sent) / static_cast<double>(options.config.drain_rate)));
    // A batch short of full: no backlog, live readings. They gather for batch_time rather than
    // go at each of the intake's 20 ms transactions: five times fewer writes at the same rate.
    if (*sent < batch_limit()) pace = std::max<Clock::duration>(pace, options.batch_time);
    if (wait_for_pace(started + pace)) break;
    const std::lock_guard lock(mutex);
    rows_ready = true;  // more may wait behind this batch
  }
  remove_unremoved();  // confirmed rows do not wait for the next start
}

Result<std::unique_ptr<Sink>> Sink::start(hub::Hub& hub, SinkOptions options) {
  const SinkKind* kind = find_sink_kind(options.config.kind);
  if (kind == nullptr) {
    return make_error(Errc::unsupported,
                      "sink kind '" + options.config.kind + "' is not built (accepted: " + sink_kind_names() + ")");
  }
  auto writer = kind->open(options);
  if (!writer) return std::move(writer).error();
  auto impl = std::make_unique<Impl>();
  impl->kind = kind;
  impl->writer = std::move(*writer);
  std::error_code made;
  std::filesystem::create_directories(options.spool_dir, made);
  if (made) return make_error(Errc::io, "spool folder " + options.spool_dir + ": " + made.message());
  impl->spool_path = (std::filesystem::path(options.spool_dir) / spool_file_name(options.config)).string();
  auto spool = Spool::open(impl->spool_path, static_cast<std::uint64_t>(options.config.spool_max_mb) * 1024 * 1024);
  if (!spool) return std::move(spool).error();
  impl->spool = std::move(*spool);
  std::vector<std::string> filters = options.config.sensors;
  if (filters.empty()) filters.emplace_back();  // one subscription to every sensor
  for (const std::string& sensor : filters) {
    auto subscription = hub.subscribe(sensor, options.queue, hub::OverflowPolicy::drop_oldest);
    if (!subscription) return std::move(subscription).error();
    (*subscription)->set_listener([items = impl->items] {
      const std::lock_guard lock(items->mutex);
      // Only the first item since the intake looked wakes it: at 2000 readings/s a wake-up
      // each cost more CPU than spooling them.
      if (items->ready) return;
      items->ready = true;
      items->wake.notify_all();
    });
    impl->subscriptions.push_back(std::move(*subscription));
  }
  impl->options = std::move(options);
  Impl* raw = impl.get();
  // Exceptions end here, never past the thread: the sink stops, the service goes on.
  const auto guarded = [raw](void (Impl::*body)()) {
    return [raw, body] {
      try {
        (raw->*body)();
      } catch (const std::exception& error) {
        raw->log(std::string("stopped: ") + error.what());
      } catch (...) {
        raw->log("stopped: unknown error");
      }
    };
  };
  impl->intake = std::thread(guarded(&Impl::run_intake));
  impl->drain = std::thread(guarded(&Impl::run_drain));
  return std::unique_ptr<Sink>(new Sink(std::move(impl)));
}

Sink::Sink(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Sink::~Sink() { stop(); }

void Sink::stop() {
  {
    const std::lock_guard lock(impl_->mutex);
    impl_->stopping = true;
    impl_->wake.notify_all();
  }
  {
    const std::lock_guard lock(impl_->items->mutex);
    impl_->items->stopping = true;
    impl_->items->wake.notify_all();
  }
  if (impl_->intake.joinable()) impl_->intake.join();
  if (impl_->drain.joinable()) impl_->drain.join();
}

SinkStats Sink::Impl::stats() {
  const SpoolStats spooled = spool->stats();
  std::uint64_t lost = 0;
  for (const hub::SubscriptionPtr& subscription : subscriptions) lost += subscription->lost();
  const std::lock_guard lock(mutex);
  SinkStats stats;
  stats.url = options.config.url;
  stats.up = up;
  stats.error = error;
  stats.written = written;
  stats.spooled = spooled.rows;
  stats.spool_bytes = spooled.bytes;
  stats.dropped = spool_dropped + lost;
  stats.rejected = rejected;
  stats.failures = failures;
  if (spooled.rows > 0) {
    const auto now =
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
            .count();
    stats.oldest_age_s = static_cast<double>(std::max<std::int64_t>(0, now - spooled.oldest_time_ns)) / 1e9;
  }
  return stats;
}

SinkStats Sink::stats() const { return impl_->stats(); }

std::string Sink::spool_path() const { return impl_->spool_path; }

}  // namespace rangekit::sinks
