// §10.1 receiver: one thread reads datagrams and queues what UdpPacketReader makes of them.
#include "rangekit/ls5/udp_receiver.hpp"

#include <array>
#include <mutex>
#include <thread>

#include "rangekit/core/stream_queue.hpp"

namespace rangekit::ls5 {
namespace {

constexpr std::chrono::milliseconds receive_slice{100};  // how often the reader looks at the stop flag

}  // namespace

struct UdpReceiver::State {
  State(UdpSocket bound, UdpReceiverOptions receiver_options)
      : socket(std::move(bound)),
        options(receiver_options),
        reader(receiver_options.address),
        queue(receiver_options.queue_capacity) {}
  UdpSocket socket;
  UdpReceiverOptions options;
  UdpPacketReader reader;
  StreamQueue<StreamItem> queue;
  std::atomic<bool> stop_requested{false};
  std::atomic<bool> finished{false};
  std::thread thread;
  std::mutex stopping;  // stop() from two threads joins once

  void run() {
    std::array<std::uint8_t, 2048> buffer{};
    std::vector<StreamItem> items;  // one datagram's, handed over with one lock and one wake-up
    while (!stop_requested.load()) {
      auto got = socket.receive(buffer, receive_slice);
      if (!got) {
        if (got.error().code == Errc::timeout) continue;
        if (got.error().code == Errc::overlong) {  // larger than 512 bytes: not an LS5 packet
          reader.read_overlong(got.error().message, items);
          queue.push_all(items);
          continue;
        }
        queue.push(StreamEvent{std::chrono::system_clock::now(), StreamEventKind::disconnected,
                               "UDP socket: " + got.error().message, 0});
        break;
      }
      reader.read(Bytes(buffer.data(), got->size), got->from, items);
      queue.push_all(items);
    }
    finished = true;
    queue.close();
  }
};

Result<std::unique_ptr<UdpReceiver>> UdpReceiver::start(const Endpoint& local, UdpReceiverOptions options) {
  auto socket = UdpSocket::bind(local);
  if (!socket) return socket.error();
  std::unique_ptr<UdpReceiver> receiver(new UdpReceiver(std::make_unique<State>(std::move(*socket), options)));
  State* state = receiver->state_.get();
  state->thread = std::thread([state] { state->run(); });
  return receiver;
}

UdpReceiver::UdpReceiver(std::unique_ptr<State> state) : state_(std::move(state)) {}

UdpReceiver::~UdpReceiver() { stop(); }

std::optional<StreamItem> UdpReceiver::next(std::chrono::milliseconds timeout) { return state_->queue.pop(timeout); }
bool UdpReceiver::next_batch(std::vector<StreamItem>& batch, std::chrono::milliseconds timeout) {
  return state_->queue.take_all(batch, timeout);
}

bool UdpReceiver::finished() const { return state_->finished.load(); }

void UdpReceiver::stop() {
  std::lock_guard stopping(state_->stopping);
  state_->stop_requested = true;
  if (state_->thread.joinable()) state_->thread.join();
  state_->finished = true;
  state_->queue.close();
}

std::uint64_t UdpReceiver::lost() const { return counters().lost_records + state_->queue.dropped(); }

Endpoint UdpReceiver::local_endpoint() const { return state_->socket.local_endpoint(); }

UdpReceiverCounters UdpReceiver::counters() const { return state_->reader.counters(); }

}  // namespace rangekit::ls5
