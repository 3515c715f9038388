#include "rangekit/ls5/udp_packet_reader.hpp"

#include <algorithm>
#include <chrono>

#include "rangekit/ls5/family.hpp"
#include "rangekit/ls5/result_code.hpp"
#include "rangekit/ls5/udp_packet.hpp"

namespace rangekit::ls5 {
namespace {

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

StreamEvent udp_event(StreamEventKind kind, std::string message, std::uint64_t count = 0) {
  return StreamEvent{std::chrono::system_clock::now(), kind, std::move(message), count};
}

}  // namespace

void UdpPacketReader::read(Bytes datagram, const Endpoint& from, std::vector<StreamItem>& out) {
  if (source_.empty() || from.host != last_from_.host || from.port != last_from_.port) {
    last_from_ = from;
    source_ = from.to_string();
  }
  const SharedName& source = source_;
  const auto now = std::chrono::system_clock::now();
  auto packet = decode_udp_packet(datagram);
  if (!packet) {
    {
      std::lock_guard lock(counters_mutex_);
      ++counters_.bad_packets;
    }
    out.emplace_back(
        udp_event(StreamEventKind::bad_frame, "UDP packet from " + source.str() + ": " + packet.error().message));
    return;
  }
  if (last_counter_ && udp_packet_is_duplicate(*last_counter_, packet->counter)) {
    // The network delivered the same datagram twice (L65): its records are not new.
    {
      std::lock_guard lock(counters_mutex_);
      ++counters_.duplicates;
    }
    out.emplace_back(udp_event(StreamEventKind::bad_frame, "UDP packet from " + source.str() + " repeats counter " +
                                                               std::to_string(packet->counter) +
                                                               ": duplicate dropped (" +
                                                               std::to_string(udp_record_count) + " records)"));
    return;
  }
  if (last_counter_) {
    // A gap is reported, never merged over (L46).
    const std::uint8_t missing = udp_packets_lost(*last_counter_, packet->counter);
    if (missing > 0) {
      const std::uint64_t records = std::uint64_t{missing} * udp_record_count;
      {
        std::lock_guard lock(counters_mutex_);
        counters_.lost_packets += missing;
        counters_.lost_records += records;
      }
      out.emplace_back(udp_event(StreamEventKind::lost_records,
                                 std::to_string(missing) + " UDP packet(s) lost before counter " +
                                     std::to_string(packet->counter) + " (" + std::to_string(records) + " records)",
                                 records));
    }
  }
  if (!last_counter_) {
    // The first packet is the link coming up: a `connected` event as the serial streams give.
    out.emplace_back(udp_event(StreamEventKind::connected, "UDP packets from " + source.str()));
  }
  last_counter_ = packet->counter;
  // Counted before its samples are handed on, so a consumer that has one sees the packet counted.
  const auto suspect = static_cast<std::uint64_t>(
      std::count_if(packet->records.begin(), packet->records.end(), [](const UdpRecord& r) { return flagged(r); }));
  {
    std::lock_guard lock(counters_mutex_);
    ++counters_.packets;
    counters_.suspect_records += suspect;
  }
  for (std::size_t i = 0; i < packet->records.size(); ++i) {
    out.emplace_back(record_sample(packet->records[i], i, *packet, source, address_, now));
  }
}

void UdpPacketReader::read_overlong(std::string message, std::vector<StreamItem>& out) {
  {
    std::lock_guard lock(counters_mutex_);
    ++counters_.bad_packets;
  }
  out.emplace_back(udp_event(StreamEventKind::bad_frame, std::move(message)));
}

UdpPacketCounters UdpPacketReader::counters() const {
  std::lock_guard lock(counters_mutex_);
  return counters_;
}

}  // namespace rangekit::ls5
