// The measurement stream (§8.13, table 9.1 ST/SB): a reader thread owns the line
// while the stream runs, turns !ddddd records into Samples and keeps the link:
// closed transport or silence -> disconnected, retry, reconnected, ST again.
#include <array>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "rangekit/core/stream_queue.hpp"
#include "rangekit/ls5/driver.hpp"
#include "rangekit/ls5/settings.hpp"

namespace rangekit::ls5 {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::chrono::milliseconds read_slice{100};  // how often the reader looks at the stop flag

StreamEvent make_event(StreamEventKind kind, std::string message, std::uint64_t count = 0) {
  return StreamEvent{std::chrono::system_clock::now(), kind, std::move(message), count};
}

}  // namespace

Sample make_ls5_sample(ResultCode code, std::optional<double> range_mm, std::string source, int address,
                       bool derivative) {
  const bool has_range = range_mm && *range_mm > 0;
  Sample sample;
  sample.time = std::chrono::system_clock::now();
  sample.device = "ls5";
  sample.source = std::move(source);
  sample.address = address;
  sample.kind = derivative ? SampleKind::ls5_derivative : SampleKind::ls5_result;
  sample.code = code.value;
  if (has_range) sample.resolution_mm = discreteness_mm(*range_mm);  // table 3.1 (L63)
  switch (code.kind) {
    case CodeKind::result:
      sample.signal = SignalState::ok;
      if (has_range && derivative) sample.derivative_mm = derivative_mm(code.value, *range_mm);  // formula 8.2
      if (has_range && !derivative) sample.distance_mm = distance_mm(code.value, *range_mm);     // formula 8.1
      break;
    case CodeKind::no_measurement_yet:
      sample.signal = SignalState::none_yet;
      break;
    case CodeKind::no_signal:
      sample.signal = SignalState::lost;
      break;
  }
  return sample;
}

struct MeasurementStream::Shared {
  explicit Shared(std::size_t capacity) : queue(capacity) {}
  StreamQueue<StreamItem> queue;
  std::mutex mutex;
  std::condition_variable wake;
  bool stop_requested = false;
  std::atomic<bool> finished{false};
  std::atomic<bool> connected{true};
  std::thread reader;
  std::mutex stopping;  // stop() from two threads (Ctrl-C and a destructor) joins once
};

Result<std::unique_ptr<MeasurementStream>> Driver::start_stream(const StreamOptions& options) {
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
  std::unique_ptr<MeasurementStream> stream(new MeasurementStream(*this, options));
  stream->shared_->reader = std::thread([raw = stream.get()] { raw->run(); });
  return stream;
}

MeasurementStream::MeasurementStream(Driver& driver, const Driver::StreamOptions& options)
    : driver_(driver), options_(options), shared_(std::make_shared<Shared>(options.queue_capacity)) {}

MeasurementStream::~MeasurementStream() { stop(); }

std::optional<StreamItem> MeasurementStream::next(std::chrono::milliseconds timeout) {
  return shared_->queue.pop(timeout);
}

bool MeasurementStream::finished() const { return shared_->finished.load(); }

std::uint64_t MeasurementStream::lost() const { return shared_->queue.dropped(); }

void MeasurementStream::stop() {
  std::lock_guard stopping(shared_->stopping);
  {
    std::lock_guard lock(shared_->mutex);
    if (shared_->stop_requested && !shared_->reader.joinable()) return;
    shared_->stop_requested = true;
  }
  shared_->wake.notify_all();
  if (shared_->reader.joinable()) shared_->reader.join();
  if (shared_->connected.load() && !shared_->finished.load()) {
    (void)driver_.stop_stream();  // best effort: any byte stops the stream anyway (L37)
  }
  shared_->finished = true;
  shared_->queue.close();
}

void MeasurementStream::run() {
  Shared& shared = *shared_;
  const std::optional<double> range_mm =
      driver_.identification_ ? std::optional<double>(driver_.identification_->range_mm) : std::nullopt;
  const int address = driver_.address();
  bool derivative = driver_.derivative_results_.value_or(false);
  std::array<std::uint8_t, 4096> buffer{};
  auto last_record = Clock::now();
  bool link_closed = false;

  auto stopping = [&shared] {
    std::lock_guard lock(shared.mutex);
    return shared.stop_requested;
  };
  auto lose_link = [&](std::string why, bool closed) {
    if (driver_.assembler_->buffered() > 0) {
      shared.queue.push(make_event(StreamEventKind::bad_frame,
                                   std::to_string(driver_.assembler_->buffered()) + " bytes of a half frame dropped"));
      driver_.assembler_->clear();
    }
    shared.queue.push(make_event(StreamEventKind::disconnected, std::move(why)));
    shared.connected = false;
    link_closed = closed;
  };

  while (!stopping()) {
    if (shared.connected.load()) {
      auto got = driver_.transport_->read_some(buffer, read_slice);
      if (!got) {
        if (got.error().code == Errc::timeout) {
          if (Clock::now() - last_record > options_.silence_timeout) {
            lose_link("no record from " + driver_.transport_name() + " for " +
                          std::to_string(options_.silence_timeout.count()) +
                          " ms (sensor power-cycled, turned off or stopped?)",
                      false);
          }
          continue;
        }
        lose_link(got.error().message, true);
        continue;
      }
      driver_.assembler_->push(Bytes(buffer.data(), *got));
      FrameAssembler::Event event;
      while (driver_.assembler_->next(event)) {
        if (event.kind == FrameAssembler::Event::Kind::rejected) {
          if (event.reason != nullptr) {
            shared.queue.push(make_event(StreamEventKind::bad_frame,
                                         std::to_string(event.rejected_bytes) + " bytes rejected: " + event.reason));
          }
          continue;
        }
        auto reply = parse_reply(event.frame);
        if (!reply) {
          shared.queue.push(make_event(StreamEventKind::bad_frame, reply.error().message));
          continue;
        }
        if (reply->kind != ReplyKind::stream_record) continue;  // e.g. a late echo
        last_record = Clock::now();
        shared.queue.push(make_ls5_sample(reply->result, range_mm, driver_.transport_name(), address, derivative));
        ++records_;  // after the push: once records() counts it, the queue (and lost()) has it
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
      Status reopened = driver_.reopen();
      if (!reopened) {
        if (reopened.error().code == Errc::unsupported) break;  // nothing to reopen with: the stream ends
        continue;
      }
      link_closed = false;
    }
    auto identified = driver_.transact(Request::simple(driver_.address(), CommandId::identification));
    if (!identified) {
      if (identified.error().code != Errc::timeout) link_closed = true;
      continue;
    }
    // A power cycle brings back 0E from ROM, which need not be what RAM held (L60).
    if (identified->identification.version.value_or(any_firmware).at_least(firmware_8_0)) {
      auto type = driver_.transact(Request::read(driver_.address(), address::result_type));
      if (!type) {
        if (type.error().code != Errc::timeout) link_closed = true;
        continue;
      }
      derivative = type->value == 0x01;
    } else {
      derivative = false;
    }
    driver_.derivative_results_ = derivative;
    auto start = encode_request(Request::simple(driver_.address(), CommandId::start_stream));
    if (!start || !driver_.transport_->write_all(start->bytes())) {
      link_closed = true;
      continue;
    }
    driver_.assembler_->clear();
    last_record = Clock::now();
    shared.connected = true;
    shared.queue.push(make_event(StreamEventKind::reconnected, "stream restarted on " + driver_.transport_name()));
  }
  if (!shared.connected.load() && !stopping()) {
    shared.finished = true;
    shared.queue.close();
  }
}

}  // namespace rangekit::ls5
