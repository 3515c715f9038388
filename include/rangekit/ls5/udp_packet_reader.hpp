// One LS5's §10.1 datagrams to samples and events, in the caller's thread: the checksum
// checked (a bad packet is counted and reported as a bad_frame event; a bad record is a
// suspect sample, its packet kept), the cyclic counter followed (a gap is a lost_records
// event with the records lost, never merged over; a repeated counter is a duplicated
// datagram, dropped, counted and reported). UdpReceiver runs it on a thread of its own; the
// service's listener runs it on its port's worker, a hand-over fewer for every packet.
#pragma once

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "rangekit/core/framer.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/core/udp.hpp"

namespace rangekit::ls5 {

struct UdpPacketCounters {
  std::uint64_t packets = 0;      // decoded
  std::uint64_t bad_packets = 0;  // wrong size or checksum
  // Records kept but flagged suspect (L85, L86): a state word not as documented, a code past 0x4000.
  std::uint64_t suspect_records = 0;
  std::uint64_t lost_packets = 0;  // counter gaps
  std::uint64_t lost_records = 0;  // lost_packets × 168
  std::uint64_t duplicates = 0;    // packets repeating the previous counter: dropped (L65)
};

class UdpPacketReader {
 public:
  explicit UdpPacketReader(int address = -1) : address_(address) {}

  // Appends to `out`, in order, what the datagram from `from` says: its 168 samples, and
  // before them a connected event (the first packet), a lost_records event (a counter gap),
  // or instead of them a bad_frame event (a bad packet, a duplicate).
  void read(Bytes datagram, const Endpoint& from, std::vector<StreamItem>& out);
  // A datagram larger than a packet (the socket's Errc::overlong): counted, reported.
  void read_overlong(std::string message, std::vector<StreamItem>& out);
  // Safe from any thread.
  [[nodiscard]] UdpPacketCounters counters() const;

 private:
  int address_;
  // Sample::source of every record, made again only when the sender changes.
  Endpoint last_from_;
  SharedName source_;
  std::optional<std::uint8_t> last_counter_;
  mutable std::mutex counters_mutex_;
  UdpPacketCounters counters_;
};

}  // namespace rangekit::ls5
