// The ULS driver's measurement stream: a reader thread that decodes lines, polls with BM
// when the unit does not stream, and reopens a lost link. Either of stream and driver may
// go first; the reader is always joined before its driver is destroyed.
#include <algorithm>
#include <condition_variable>
#include <mutex>
#include <utility>

#include "rangekit/core/stream_queue.hpp"
#include "rangekit/uls/driver.hpp"
#include "rangekit/uls/family.hpp"
#include "rangekit/uls/formulas.hpp"
#include "uls/driver/binning_array.hpp"

namespace rangekit::uls {

using namespace std::chrono_literals;

namespace {

// A Transport that borrows another one: lets probe() run a Driver on a port it does not own.
class BorrowedTransport final : public Transport {
 public:
  explicit BorrowedTransport(Transport& inner) : inner_(inner) {}
  Status write_all(Bytes data) override { return inner_.write_all(data); }
  Result<std::size_t> read_some(std::span<std::uint8_t> out, std::chrono::milliseconds timeout) override {
    return inner_.read_some(out, timeout);
  }
  void close() noexcept override {}
  [[nodiscard]] std::string name() const override { return inner_.name(); }

 private:
  Transport& inner_;
};

}  // namespace

namespace detail {

struct LiveStream {
  LiveStream(std::size_t capacity, std::chrono::microseconds gather) : queue(capacity, gather) {}
  StreamQueue<StreamItem> queue;
  std::atomic<bool> stop_requested{false};
  // The reader's read_gather wait, ended early by a stop.
  std::mutex wake_mutex;
  std::condition_variable wake;
  std::atomic<bool> finished{false};  // the reader has ended (stopped, or the link lost for good)
  std::atomic<std::uint64_t> records{0};
  std::thread reader;
  // One ending at a time (the stream's stop from two threads, the driver's stop_stream,
  // its destructor); guards everything below and the join.
  std::mutex stopping;
  bool ended = false;              // the unit has been left as asked: a second stop does nothing
  bool started_measuring = false;  // the stream's GO started an idle unit (U86)
  Driver* driver = nullptr;        // cleared when the driver goes away or starts another stream
};

void stop_live_stream(LiveStream& live, AfterStream after, bool detach) {
  std::lock_guard stopping(live.stopping);
  if (!live.ended) {
    live.ended = true;
    {
      std::lock_guard lock(live.wake_mutex);  // a reader about to wait sees it, or is woken
      live.stop_requested = true;
    }
    live.wake.notify_all();
    if (live.reader.joinable()) live.reader.join();
    if (live.driver != nullptr) live.driver->end_stream(live, after);
    live.finished = true;
    live.queue.close();  // wakes a consumer waiting in next()
  }
  if (detach) live.driver = nullptr;
}

}  // namespace detail

MeasurementStream::MeasurementStream(std::shared_ptr<detail::LiveStream> live) : live_(std::move(live)) {}
MeasurementStream::~MeasurementStream() { stop(); }
std::optional<StreamItem> MeasurementStream::next(std::chrono::milliseconds timeout) {
  return live_->queue.pop(timeout);
}
bool MeasurementStream::next_batch(std::vector<StreamItem>& batch, std::chrono::milliseconds timeout) {
  return live_->queue.take_all(batch, timeout);
}
bool MeasurementStream::finished() const { return live_->finished.load() && live_->queue.size() == 0; }
void MeasurementStream::stop() { stop(AfterStream::as_found); }
void MeasurementStream::stop(AfterStream after) { detail::stop_live_stream(*live_, after); }
std::uint64_t MeasurementStream::lost() const { return live_->queue.dropped(); }
std::uint64_t MeasurementStream::records() const noexcept { return live_->records.load(); }

void Driver::emit_sample(Sample sample) {
  last_measurement_ = std::chrono::steady_clock::now();
  live_->queue.push(StreamItem{std::move(sample)});
  ++live_->records;  // after the push: once records() counts it, the queue (and lost()) has it
}

void Driver::emit_event(StreamEventKind kind, std::string message) {
  StreamEvent event;
  event.time = std::chrono::system_clock::now();
  event.kind = kind;
  event.message = std::move(message);
  live_->queue.push(StreamItem{std::move(event)});
}

void Driver::handle_measurement(const Measurement& measurement) {
  const int address = measurement.source.addressed ? measurement.source.byte : -1;
  if (const auto* target = std::get_if<BinningTarget>(&measurement.reading)) {
    // U10: one sample per complete target array `BM,i,m,n,s`.
    const detail::BinningArray step = detail::collect_binning_target(partial_targets_, *target);
    if (step == detail::BinningArray::out_of_order) {
      if (collecting_) emit_event(StreamEventKind::bad_frame, "binning target array out of order; dropped");
      return;
    }
    if (step == detail::BinningArray::incomplete) return;
    Sample sample = sample_from_reading(measurement.reading, address, source_name_);
    // Copied into the sample's own inline storage (at most 15, the decoder checks), so
    // neither side allocates: the collecting vector keeps its storage for the next burst.
    sample.targets.assign(partial_targets_.begin(), partial_targets_.end());
    partial_targets_.clear();
    if (collecting_) emit_sample(std::move(sample));
    return;
  }
  if (collecting_) emit_sample(sample_from_reading(measurement.reading, address, source_name_));
}

// A look-down poll reads the state the last edge left (§2 Single Measurement, "the most recent
// measurement"): the same answer again is no new edge (U87).
bool same_look_down_answer(const Sample& a, const Sample& b) noexcept {
  return a.kind == b.kind && a.get(channel::presence) == b.get(channel::presence) &&
         a.get(channel::pulses_between_events) == b.get(channel::pulses_between_events) &&
         a.get(channel::pulses_overflow).value_or(false) == b.get(channel::pulses_overflow).value_or(false) &&
         a.get(channel::error) == b.get(channel::error);
}

bool Driver::repeats_last_poll(const Sample& sample) {
  const bool same = last_polled_ && same_look_down_answer(*last_polled_, sample);
  last_polled_ = sample;
  return same;
}

Result<Driver::PollPlan> Driver::poll_plan(Mode mode) {
  PollPlan plan;
  plan.look_down = mode == Mode::look_down;
  if (plan.look_down) {
    plan.period = 50ms;
    return plan;
  }
  auto rates = prf();
  if (!rates) return rates.error();
  auto ppm = pulses_per_measurement();
  if (!ppm) return ppm.error();
  const std::size_t index = mode == Mode::averaging ? 0 : 1;
  const double seconds = output_period_s((*ppm)[index], (*rates)[index]);
  // Rounded up: polling faster than the unit measures returns a measurement twice (U89).
  const auto period = std::chrono::ceil<std::chrono::microseconds>(std::chrono::duration<double>(seconds));
  plan.period = std::clamp<std::chrono::microseconds>(period, 5ms, 10000ms);
  return plan;
}

Status Driver::begin_measuring(bool reconnecting) {
  {
    // Lines that arrive before MM/DM/MU/TB are read again are not decoded (U85).
    std::lock_guard lock(state_mutex_);
    context_known_ = false;
  }
  auto context = read_context();
  if (!context) return context.error();
  StreamMode mode = requested_mode_;
  if (mode == StreamMode::automatic) {
    auto continuous_on = continuous();
    if (!continuous_on) return continuous_on.error();
    mode = *continuous_on ? StreamMode::continuous : StreamMode::polled;
  }
  // The poll period is the output period PPM / PRF of the mode (§2); look down reports changes.
  auto plan = poll_plan(context->mode);
  if (!plan) return plan.error();
  poll_plan_ = *plan;
  last_polled_.reset();
  partial_targets_.clear();
  active_mode_ = mode;
  // §2 ULS Autostart: a unit may measure already (MA, another host). GO would restart it
  // (in look down it references again), so it is sent only to an idle unit (U86).
  auto state = status();
  if (!state) return state.error();
  const bool measuring = state->measuring();
  // From here lines are decoded with the unit's own settings and belong to the
  // stream. Announced before GO so the event comes ahead of the first new sample.
  collecting_ = true;
  if (reconnecting) {
    emit_event(StreamEventKind::reconnected, options_.source + ": link back, measuring again");
  } else {
    emit_event(StreamEventKind::connected,
               options_.source + ": measuring, " + (mode == StreamMode::polled ? "polled with BM" : "continuous"));
  }
  if (!measuring) {
    if (auto started = start_measuring(); !started) return started;
    if (!reconnecting) live_->started_measuring = true;
  }
  last_measurement_ = std::chrono::steady_clock::now();
  return ok_status();
}

Result<std::unique_ptr<MeasurementStream>> Driver::start_stream(StreamMode mode) {
  std::lock_guard control(stream_control_mutex_);
  if (streaming_) return make_error(Errc::unsupported, "the stream is already running");
  std::shared_ptr<detail::LiveStream> previous;
  {
    std::lock_guard lock(live_mutex_);
    previous = live_;
  }
  // A stream that ended by itself (link lost for good) is joined and forgets this
  // driver: its object, if it lives on, can no longer touch the new stream's unit.
  if (previous) detail::stop_live_stream(*previous, AfterStream::as_found, true);
  auto live = std::make_shared<detail::LiveStream>(options_.queue_capacity, options_.gather);
  live->driver = this;
  {
    std::lock_guard lock(live_mutex_);
    live_ = live;
  }
  requested_mode_ = mode;
  if (auto begun = begin_measuring(false); !begun) {
    collecting_ = false;
    live->driver = nullptr;  // a `connected` announced before a refused GO goes with it
    std::lock_guard lock(live_mutex_);
    live_.reset();
    return begun.error();
  }
  {
    // The stream's ending lock first, then the request lock: the order a stop takes them
    // in (stop_live_stream holds `stopping` while end_stream's ST takes the request lock).
    std::lock_guard stopping(live->stopping);
    // No caller is between pumps of its own when the reader takes the link: one
    // waiting for the lock sees streaming_ and lets the reader hand its reply over.
    std::lock_guard request_lock(request_mutex_);
    {
      std::lock_guard lock(state_mutex_);  // set_address checks it under this lock
      streaming_ = true;
    }
    live->reader = std::thread([this, raw = live.get()] { reader_loop(*raw); });
  }
  return std::unique_ptr<MeasurementStream>(new MeasurementStream(std::move(live)));
}

void Driver::stop_stream(AfterStream after) {
  std::lock_guard control(stream_control_mutex_);
  std::shared_ptr<detail::LiveStream> live;
  {
    std::lock_guard lock(live_mutex_);
    live = live_;
  }
  if (live) detail::stop_live_stream(*live, after);
}

void Driver::end_stream(detail::LiveStream& live, AfterStream after) {
  {
    // Under the mutex a waiting caller checks it with, so the wake-up is not missed.
    std::lock_guard lock(state_mutex_);
    streaming_ = false;
    collecting_ = false;
  }
  reply_ready_.notify_all();
  const bool started_by_us = std::exchange(live.started_measuring, false);
  const bool send_stop = after == AfterStream::stop_measuring || (after == AfterStream::as_found && started_by_us);
  if (send_stop && connected()) (void)action("ST");
}

bool Driver::reconnect(detail::LiveStream& live) {
  const auto began = std::chrono::steady_clock::now();
  while (!live.stop_requested) {
    if (options_.give_up_after && std::chrono::steady_clock::now() - began > *options_.give_up_after) return false;
    // Wait in small steps so stop() is honoured quickly.
    const auto until = std::chrono::steady_clock::now() + options_.reconnect_interval;
    while (!live.stop_requested && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(10ms);
    if (live.stop_requested) return false;
    auto reopened = reopen_();
    if (!reopened) continue;
    (void)replace_transport(std::move(*reopened));  // on the reader thread: always accepted
    if (auto begun = begin_measuring(true); !begun) {
      // The port is back but the unit does not answer yet (still powering up).
      std::lock_guard lock(transport_mutex_);
      transport_.reset();
      continue;
    }
    return true;
  }
  return false;
}

void Driver::reader_loop(detail::LiveStream& live) {
  reader_id_ = std::this_thread::get_id();
  auto next_poll = std::chrono::steady_clock::now();
  while (!live.stop_requested) {
    Status step = ok_status();
    const auto now = std::chrono::steady_clock::now();
    if (active_mode_ == StreamMode::polled && now >= next_poll) {
      Sample sample;
      auto done = transact(*find_command("BM"), {}, Expect::measurement, 1, options_.measure_timeout, &sample);
      // BM answers "the most recent measurement" (§2 Single Measurement), and the first
      // answer waits for the first measurement: the next new one is due one output period
      // after the answer, not after the request (U89).
      next_poll = std::chrono::steady_clock::now() + poll_plan_.period;
      if (done) {
        if (!poll_plan_.look_down || !repeats_last_poll(sample)) emit_sample(std::move(sample));
      } else if (done.error().code == Errc::closed || done.error().code == Errc::io) {
        step = done.error();
      } else if (done.error().code == Errc::device_error) {
        emit_event(StreamEventKind::device_error, done.error().message);
      }
    } else {
      const auto wait =
          active_mode_ == StreamMode::polled
              ? std::clamp(std::chrono::duration_cast<std::chrono::milliseconds>(next_poll - now), 1ms, 50ms)
              : 50ms;
      std::size_t got = 0;
      step = pump(wait, &got);
      // Let the next lines collect in the port before reading again (read_gather).
      if (step && got > 0 && active_mode_ != StreamMode::polled && options_.read_gather.count() > 0) {
        std::unique_lock lock(live.wake_mutex);
        live.wake.wait_for(lock, options_.read_gather, [&live] { return live.stop_requested.load(); });
      }
      // No continuous lines on this port (MO sends them elsewhere): poll instead (U62).
      // Not in look down, which is silent while nothing changes (U87).
      if (step && requested_mode_ == StreamMode::automatic && active_mode_ == StreamMode::continuous &&
          !poll_plan_.look_down &&
          std::chrono::steady_clock::now() - last_measurement_ >
              std::max<std::chrono::microseconds>(3 * poll_plan_.period, 1500ms)) {
        active_mode_ = StreamMode::polled;
        // Said, not done silently: the data now come one BM at a time, and a unit that
        // sends its lines to the other port (MO) is worth knowing about.
        emit_event(StreamEventKind::polling,
                   options_.source +
                       ": no continuous lines on this port (is continuous output off, or sent to the other port?): "
                       "polling every " +
                       std::to_string(std::chrono::ceil<std::chrono::milliseconds>(poll_plan_.period).count()) + " ms");
      }
    }
    if (step) continue;
    // The link went away (U63).
    emit_event(StreamEventKind::disconnected, step.error().message);
    {
      std::lock_guard lock(transport_mutex_);
      if (transport_) transport_->close();
      transport_.reset();
    }
    assembler_.clear();
    partial_targets_.clear();
    if (!reopen_ || !reconnect(live)) break;
    next_poll = std::chrono::steady_clock::now();
  }
  reader_id_ = std::thread::id();
  {
    std::lock_guard lock(state_mutex_);  // see stop_stream
    streaming_ = false;                  // callers pump for themselves again
    collecting_ = false;                 // nothing more goes to the closed queue
  }
  reply_ready_.notify_all();
  live.finished = true;
  live.queue.close();
}

Result<ProbeResult> probe(Transport& transport, std::optional<std::uint8_t> address,
                          std::chrono::milliseconds timeout) {
  DriverOptions options;
  options.address = address;
  options.timeout = timeout;
  options.read_retries = 0;
  Driver driver(std::make_unique<BorrowedTransport>(transport), options);
  // ID and US only read (§8): the unit is left as it was.
  auto version = driver.version();
  if (!version) return version.error();
  ProbeResult result;
  result.addressed = address.has_value();
  result.address = address;
  result.version = *version;
  auto status = driver.status();
  if (!status) return status.error();
  result.status = *status;
  return result;
}

}  // namespace rangekit::uls
