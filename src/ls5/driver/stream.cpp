// The measurement stream (§8.13, table 9.1 ST/SB): a reader thread owns the line
// while the stream runs, turns !ddddd records into Samples and keeps the link:
// closed transport or silence -> disconnected, retry, reconnected, ST again.
#include <array>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "rangekit/core/stream_queue.hpp"
#include "rangekit/ls5/driver.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/ls5/settings.hpp"

namespace rangekit::ls5 {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::chrono::milliseconds read_slice{100};  // how often the reader looks at the stop flag

StreamEvent make_event(StreamEventKind kind, std::string message, std::uint64_t count = 0) {
  return StreamEvent{std::chrono::system_clock::now(), kind, std::move(message), count};
}

}  // namespace

Sample make_ls5_sample(ResultCode code, std::optional<double> range_mm, SharedName source, int address,
                       bool derivative) {
  const bool has_range = range_mm && *range_mm > 0;
  Sample sample;
  sample.time = std::chrono::system_clock::now();
  sample.device = family().name;
  sample.source = std::move(source);
  sample.address = address;
  sample.kind = derivative ? kind::derivative : kind::result;
  sample.set(channel::code, code.value);
  if (has_range) sample.set(channel::resolution_mm, discreteness_mm(*range_mm));  // table 3.1 (L63)
  switch (code.kind) {
    case CodeKind::result:
      sample.set(channel::signal, SignalState::ok);
      if (has_range && derivative)
        sample.set(channel::derivative_mm, derivative_mm(code.value, *range_mm));  // formula 8.2
      if (has_range && !derivative)
        sample.set(channel::distance_mm, distance_mm(code.value, *range_mm));  // formula 8.1
      break;
    case CodeKind::no_measurement_yet:
      sample.set(channel::signal, SignalState::none_yet);
      break;
    case CodeKind::no_signal:
      sample.set(channel::signal, SignalState::lost);
      break;
  }
  return sample;
}

namespace detail {

struct LiveStream {
  LiveStream(std::size_t capacity, std::chrono::microseconds gather) : queue(capacity, gather) {}
  StreamQueue<StreamItem> queue;
  std::mutex mutex;
  std::condition_variable wake;
  bool stop_requested = false;
  std::atomic<bool> finished{false};
  std::atomic<bool> connected{true};
  std::atomic<bool> owns_line{true};  // the reader runs: the driver refuses calls
  std::atomic<std::thread::id> reader_id{};
  std::uint8_t address = 0x01;  // the driver's address at start; set_address later does not move the stream
  std::string port;             // the link's name at start, for refusals (the reader may reopen the link)
  std::thread reader;
  std::mutex stopping;       // stop() from two threads (Ctrl-C and a destructor) joins once; guards driver
  Driver* driver = nullptr;  // cleared when the driver goes away (after it stopped the stream)
};

namespace {}  // namespace

// Joins the reader, then sends SB (any byte stops the stream anyway, L37): its result.
Status stop_live_stream(LiveStream& live) {
  std::lock_guard stopping(live.stopping);
  {
    std::lock_guard lock(live.mutex);
    if (live.stop_requested && !live.reader.joinable()) return ok_status();
    live.stop_requested = true;
  }
  live.wake.notify_all();
  if (live.reader.joinable()) live.reader.join();
  live.owns_line = false;
  Status stopped = ok_status();
  if (live.driver != nullptr && live.connected.load() && !live.finished.load()) {
    stopped = live.driver->send_stop_stream();
  }
  live.finished = true;
  live.queue.close();
  return stopped;
}

namespace {

// The driver no longer exists, or no longer belongs to this (finished) stream.
void detach_driver(LiveStream& live) {
  std::lock_guard stopping(live.stopping);
  live.driver = nullptr;
}

}  // namespace
}  // namespace detail

Driver::~Driver() {
  if (!live_stream_) return;
  (void)detail::stop_live_stream(*live_stream_);  // the sensor is left idle (SB) and the reader joined
  detail::detach_driver(*live_stream_);
}

bool Driver::streaming() const noexcept { return live_stream_ && live_stream_->owns_line.load(); }

Status Driver::refuse_while_streaming(std::string_view call) const {
  if (!streaming() || std::this_thread::get_id() == live_stream_->reader_id.load()) return ok_status();
  return make_error(Errc::unsupported, std::string(call) + " refused: the measurement stream started on " +
                                           live_stream_->port +
                                           " holds the line; stop or destroy the stream first (SB ends it)");
}

Result<std::unique_ptr<MeasurementStream>> Driver::start_stream(const StreamOptions& options) {
  if (auto refused = refuse_while_streaming("start_stream"); !refused) return refused.error();
  if (!identification_) {
    auto identified = identify();  // the range turns codes into mm
    if (!identified) return identified.error();
  }
  if (options.thinning) {
    Status written = write_parameter(address::thinning, *options.thinning);
    if (!written) return written.error();
  }
  auto derivative = results_are_derivative();  // how to read the records (§8.9, L60)
  if (!derivative) return derivative.error();
  auto start = encode_request(Request::simple(options_.address, CommandId::start_stream));
  if (!start) return start.error();
  Status sent = transport_->write_all(start->bytes());
  if (!sent) return sent.error();
  if (live_stream_) detail::detach_driver(*live_stream_);  // a finished stream: it sends nothing more
  auto live = std::make_shared<detail::LiveStream>(options.queue_capacity, options.gather);
  live->driver = this;
  live->address = options_.address;
  live->port = transport_name();
  live_stream_ = live;
  // The first item, as in the ULS stream: the link is up and the sensor streams.
  live->queue.push(make_event(StreamEventKind::connected, transport_name() + ": streaming (ST)"));
  std::unique_ptr<MeasurementStream> stream(new MeasurementStream(std::move(live), options));
  stream->shared_->reader = std::thread([raw = stream.get()] { raw->run(); });
  return stream;
}

MeasurementStream::MeasurementStream(std::shared_ptr<detail::LiveStream> shared, const Driver::StreamOptions& options)
    : options_(options), shared_(std::move(shared)) {}

MeasurementStream::~MeasurementStream() { stop(); }

std::optional<StreamItem> MeasurementStream::next(std::chrono::milliseconds timeout) {
  return shared_->queue.pop(timeout);
}

bool MeasurementStream::next_batch(std::vector<StreamItem>& batch, std::chrono::milliseconds timeout) {
  return shared_->queue.take_all(batch, timeout);
}

bool MeasurementStream::finished() const { return shared_->finished.load(); }

std::uint64_t MeasurementStream::lost() const { return shared_->queue.dropped(); }

void MeasurementStream::stop() { (void)detail::stop_live_stream(*shared_); }

Status Driver::stop_stream() {
  const bool on_reader = live_stream_ && std::this_thread::get_id() == live_stream_->reader_id.load();
  if (streaming() && !on_reader) return detail::stop_live_stream(*live_stream_);
  return send_stop_stream();
}

void MeasurementStream::run() {
  detail::LiveStream& shared = *shared_;
  shared.reader_id = std::this_thread::get_id();  // the driver answers this thread's requests
  // Valid until this thread is joined: the driver stops the stream before it goes away.
  Driver& driver = *shared.driver;
  const std::optional<double> range_mm =
      driver.identification_ ? std::optional<double>(driver.identification_->range_mm) : std::nullopt;
  const int address = shared.address;
  bool derivative = driver.derivative_results_.value_or(false);
  // Sample::source of every record: built once, not per record; again after a reopen.
  SharedName source = driver.transport_name();
  std::array<std::uint8_t, 4096> buffer{};
  std::vector<StreamItem> decoded;  // what one read decoded, handed over at once; storage reused
  auto last_record = Clock::now();
  bool link_closed = false;

  auto stopping = [&shared] {
    std::lock_guard lock(shared.mutex);
    return shared.stop_requested;
  };
  auto lose_link = [&](std::string why, bool closed) {
    if (driver.assembler_->buffered() > 0) {
      shared.queue.push(make_event(StreamEventKind::bad_frame,
                                   std::to_string(driver.assembler_->buffered()) + " bytes of a half frame dropped"));
      driver.assembler_->clear();
    }
    shared.queue.push(make_event(StreamEventKind::disconnected, std::move(why)));
    shared.connected = false;
    link_closed = closed;
  };

  while (!stopping()) {
    if (shared.connected.load()) {
      auto got = driver.transport_->read_some(buffer, read_slice);
      if (!got) {
        if (got.error().code == Errc::timeout) {
          if (Clock::now() - last_record > options_.silence_timeout) {
            lose_link("no record from " + driver.transport_name() + " for " +
                          std::to_string(options_.silence_timeout.count()) +
                          " ms (sensor power-cycled, turned off or stopped?)",
                      false);
          }
          continue;
        }
        lose_link(got.error().message, true);
        continue;
      }
      std::uint64_t records_read = 0;
      auto on_record = [&](ResultCode code) {
        last_record = Clock::now();
        decoded.push_back(make_ls5_sample(code, range_mm, source, address, derivative));
        ++records_read;
      };
      auto on_reply = [&](Bytes, const Result<Reply>& reply) {
        if (!reply) {
          decoded.push_back(make_event(StreamEventKind::bad_frame, reply.error().message));
          return;
        }
        if (reply->kind == ReplyKind::stream_record) on_record(reply->result);  // else e.g. a late echo
      };
      auto on_rejected = [&](const FrameAssembler::Event& event) {
        if (event.reason == nullptr) return;
        decoded.push_back(make_event(StreamEventKind::bad_frame,
                                     std::to_string(event.rejected_bytes) + " bytes rejected: " + event.reason));
      };
      // Stream records straight from the buffer, everything else through parse_reply.
      // A read that does not fit beside a half record is fed in parts, decoded in between.
      feed_all(*driver.assembler_, Bytes(buffer.data(), *got),
               [&] { decode_replies(*driver.assembler_, on_record, on_reply, on_rejected); });
      // What one read decoded goes over in one batch (one lock, at most one wake-up).
      shared.queue.push_all(decoded);
      records_ += records_read;  // after the push: once records() counts them, the queue (and lost()) has them
      // Let the next records collect in the port before reading again: one read, and one
      // hand-over, per read_gather instead of per record. A stop ends the wait.
      if (*got > 0 && options_.read_gather.count() > 0) {
        std::unique_lock lock(shared.mutex);
        shared.wake.wait_for(lock, options_.read_gather, [&shared] { return shared.stop_requested; });
      }
      continue;
    }

    // Not connected: wait one interval (or until stop), then try to get the stream back.
    {
      std::unique_lock lock(shared.mutex);
      shared.wake.wait_for(lock, options_.reconnect_interval, [&shared] { return shared.stop_requested; });
      if (shared.stop_requested) break;
    }
    if (link_closed) {
      Status reopened = driver.reopen();
      if (!reopened) {
        if (reopened.error().code == Errc::unsupported) break;  // nothing to reopen with: the stream ends
        continue;
      }
      link_closed = false;
      source = driver.transport_name();
    }
    auto identified = driver.transact(Request::simple(shared.address, CommandId::identification));
    if (!identified) {
      if (identified.error().code != Errc::timeout) link_closed = true;
      continue;
    }
    // A power cycle brings back 0E from ROM, which need not be what RAM held (L60).
    if (identified->identification.version.value_or(any_firmware).at_least(firmware_8_0)) {
      auto type = driver.transact(Request::read(shared.address, address::result_type));
      if (!type) {
        if (type.error().code != Errc::timeout) link_closed = true;
        continue;
      }
      derivative = type->value == 0x01;
    } else {
      derivative = false;
    }
    driver.derivative_results_ = derivative;
    auto start = encode_request(Request::simple(shared.address, CommandId::start_stream));
    if (!start || !driver.transport_->write_all(start->bytes())) {
      link_closed = true;
      continue;
    }
    driver.assembler_->clear();
    last_record = Clock::now();
    shared.connected = true;
    shared.queue.push(make_event(StreamEventKind::reconnected, "stream restarted on " + driver.transport_name()));
  }
  shared.owns_line = false;  // the driver may be used again
  if (!shared.connected.load() && !stopping()) {
    shared.finished = true;
    shared.queue.close();
  }
}

}  // namespace rangekit::ls5
