// §10.1 receiver: one thread reads datagrams, decodes them with the codec and
// queues one Sample per record; checksum failures and counter gaps become events.
#include "rangekit/ls5/udp_receiver.hpp"

#include <algorithm>
#include <array>
#include <mutex>
#include <thread>

#include "rangekit/core/stream_queue.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/ls5/result_code.hpp"
#include "rangekit/ls5/udp_packet.hpp"

namespace rangekit::ls5 {
namespace {

constexpr std::chrono::milliseconds receive_slice{100};  // how often the reader looks at the stop flag

Sample record_sample(const UdpRecord& record, std::size_t index, const UdpPacket& packet, const SharedName& source,
                     int address, std::chrono::system_clock::time_point time) {
  Sample sample;
  sample.time = time;
  sample.device = family().name;
  sample.source = source;
  sample.address = address;
  // State bit 3: "the result corresponds to the distance derivative" (§10.1, L60).
  sample.kind = record.derivative() ? kind::derivative : kind::result;
  sample.set(channel::code, record.code);  // the §10.1 code, 0-0x4000 (L45)
  if (packet.range_mm > 0) sample.set(channel::resolution_mm, discreteness_mm(packet.range_mm));  // table 3.1 (L63)
  if (auto state = check_udp_state(record.state); !state) {
    // Kept in its place with its code, but a word not as documented says nothing sure: no
    // signal, no value (L85).
    sample.suspect = true;
    sample.suspect_reason = "measurement " + std::to_string(index + 1) + " of the UDP packet: " + state.error().message;
    return sample;
  }
  if (!record.measured()) {
    sample.set(channel::signal, SignalState::none_yet);
  } else if (!record.in_range()) {
    sample.set(channel::signal, SignalState::lost);
  } else if (record.code > udp_full_scale_code) {
    // Past 0x4000, the end of the range of formula 10.1: out of range whatever bit 2 says (L86).
    sample.set(channel::signal, SignalState::lost);
    sample.suspect = true;
    sample.suspect_reason = "code " + std::to_string(record.code) + " is above 0x4000 (16384), the end of the range, " +
                            "while the state word says in range: out of range";
  } else {
    sample.set(channel::signal, SignalState::ok);
    if (record.derivative()) {
      auto derivative = udp_derivative_mm(record, packet.range_mm);  // formula 8.2 scaled to 0x4000 (L87)
      if (derivative) sample.set(channel::derivative_mm, *derivative);
    } else {
      auto distance = udp_distance_mm(record, packet.range_mm);  // formula 10.1
      if (distance) sample.set(channel::distance_mm, *distance);
    }
  }
  return sample;
}

// Records kept but flagged suspect: a state word not as documented, or a code past 0x4000.
bool flagged(const UdpRecord& record) {
  return !check_udp_state(record.state) ||
         (record.measured() && record.in_range() && record.code > udp_full_scale_code);
}

StreamEvent make_event(StreamEventKind kind, std::string message, std::uint64_t count = 0) {
  return StreamEvent{std::chrono::system_clock::now(), kind, std::move(message), count};
}

}  // namespace

struct UdpReceiver::State {
  State(UdpSocket bound, UdpReceiverOptions receiver_options)
      : socket(std::move(bound)), options(receiver_options), queue(receiver_options.queue_capacity) {}
  UdpSocket socket;
  UdpReceiverOptions options;
  StreamQueue<StreamItem> queue;
  std::atomic<bool> stop_requested{false};
  std::atomic<bool> finished{false};
  mutable std::mutex counters_mutex;
  UdpReceiverCounters counters;
  std::optional<std::uint8_t> last_counter;
  std::thread reader;
  std::mutex stopping;  // stop() from two threads joins once

  void handle(Bytes datagram, const SharedName& source) {
    const auto now = std::chrono::system_clock::now();
    auto packet = decode_udp_packet(datagram);
    if (!packet) {
      {
        std::lock_guard lock(counters_mutex);
        ++counters.bad_packets;
      }
      queue.push(
          make_event(StreamEventKind::bad_frame, "UDP packet from " + source.str() + ": " + packet.error().message));
      return;
    }
    if (last_counter && udp_packet_is_duplicate(*last_counter, packet->counter)) {
      // The network delivered the same datagram twice (L65): its records are not new.
      {
        std::lock_guard lock(counters_mutex);
        ++counters.duplicates;
      }
      queue.push(make_event(StreamEventKind::bad_frame, "UDP packet from " + source.str() + " repeats counter " +
                                                            std::to_string(packet->counter) + ": duplicate dropped (" +
                                                            std::to_string(udp_record_count) + " records)"));
      return;
    }
    if (last_counter) {
      // A gap is reported, never merged over (L46).
      const std::uint8_t missing = udp_packets_lost(*last_counter, packet->counter);
      if (missing > 0) {
        const std::uint64_t records = std::uint64_t{missing} * udp_record_count;
        {
          std::lock_guard lock(counters_mutex);
          counters.lost_packets += missing;
          counters.lost_records += records;
        }
        queue.push(make_event(StreamEventKind::lost_records,
                              std::to_string(missing) + " UDP packet(s) lost before counter " +
                                  std::to_string(packet->counter) + " (" + std::to_string(records) + " records)",
                              records));
      }
    }
    if (!last_counter) {
      // The first packet is the link coming up: a `connected` event as the serial streams give.
      queue.push(make_event(StreamEventKind::connected, "UDP packets from " + source.str()));
    }
    last_counter = packet->counter;
    // Counted before its samples are queued, so a consumer that has one sees the packet counted.
    const auto suspect = static_cast<std::uint64_t>(
        std::count_if(packet->records.begin(), packet->records.end(), [](const UdpRecord& r) { return flagged(r); }));
    {
      std::lock_guard lock(counters_mutex);
      ++counters.packets;
      counters.suspect_records += suspect;
    }
    for (std::size_t i = 0; i < packet->records.size(); ++i) {
      queue.push(record_sample(packet->records[i], i, *packet, source, options.address, now));
    }
  }

  void run() {
    std::array<std::uint8_t, 2048> buffer{};
    // Sample::source of every record, made again only when the sender changes.
    Endpoint last_from;
    SharedName source;
    while (!stop_requested.load()) {
      auto got = socket.receive(buffer, receive_slice);
      if (!got) {
        if (got.error().code == Errc::timeout) continue;
        if (got.error().code == Errc::overlong) {  // larger than 512 bytes: not an LS5 packet
          {
            std::lock_guard lock(counters_mutex);
            ++counters.bad_packets;
          }
          queue.push(make_event(StreamEventKind::bad_frame, got.error().message));
          continue;
        }
        queue.push(make_event(StreamEventKind::disconnected, "UDP socket: " + got.error().message));
        break;
      }
      if (source.empty() || got->from.host != last_from.host || got->from.port != last_from.port) {
        last_from = got->from;
        source = got->from.to_string();
      }
      handle(Bytes(buffer.data(), got->size), source);
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
  state->reader = std::thread([state] { state->run(); });
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
  if (state_->reader.joinable()) state_->reader.join();
  state_->finished = true;
  state_->queue.close();
}

std::uint64_t UdpReceiver::lost() const { return counters().lost_records + state_->queue.dropped(); }

Endpoint UdpReceiver::local_endpoint() const { return state_->socket.local_endpoint(); }

UdpReceiverCounters UdpReceiver::counters() const {
  std::lock_guard lock(state_->counters_mutex);
  return state_->counters;
}

}  // namespace rangekit::ls5
