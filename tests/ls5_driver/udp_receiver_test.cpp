// The §10.1 receiver on loopback UDP with packets built byte by byte from the
// table in §10.1: records, checksum failures, counter gaps and the 8-bit wrap.
#include <gtest/gtest.h>

#include <array>

#include "rangekit/ls5/family.hpp"
#include "rangekit/ls5/udp_receiver.hpp"

using namespace rangekit;
using namespace rangekit::ls5;
using namespace std::chrono_literals;

namespace {

using Packet = std::array<std::uint8_t, 512>;

// §10.1: 168 × (code low, code high, state), serial, lower boundary, range (low byte
// first), counter at 510, checksum at 511 = XOR of every byte but the counter and itself.
Packet build_packet(std::uint8_t counter, std::uint16_t code = 0x2000, std::uint8_t state = 0x07) {
  Packet packet{};
  for (std::size_t record = 0; record < 168; ++record) {
    packet[record * 3] = static_cast<std::uint8_t>(code & 0xFF);
    packet[record * 3 + 1] = static_cast<std::uint8_t>(code >> 8);
    packet[record * 3 + 2] = state;
  }
  packet[504] = 157;  // serial 157
  packet[505] = 0;
  packet[506] = 10;  // lower boundary 10 mm
  packet[507] = 0;
  packet[508] = 100;  // range 100 mm
  packet[509] = 0;
  packet[510] = counter;
  std::uint8_t checksum = 0;
  for (std::size_t i = 0; i < 510; ++i) checksum = static_cast<std::uint8_t>(checksum ^ packet[i]);
  packet[511] = checksum;
  return packet;
}

struct UdpRig {
  std::unique_ptr<UdpReceiver> receiver;
  std::optional<UdpSocket> sender;
  UdpRig() {
    auto started = UdpReceiver::start(Endpoint{"127.0.0.1", 0}, UdpReceiverOptions{65536, 1});
    EXPECT_TRUE(started) << started.error().message;
    if (started) receiver = std::move(*started);
    auto socket = UdpSocket::bind(Endpoint{"127.0.0.1", 0});
    EXPECT_TRUE(socket) << socket.error().message;
    if (socket) sender.emplace(std::move(*socket));
  }
  void send(const Packet& packet) { ASSERT_TRUE(sender->send_to(packet, receiver->local_endpoint())); }
  void send_bytes(Bytes bytes) { ASSERT_TRUE(sender->send_to(bytes, receiver->local_endpoint())); }
  // Next item within 5 s; the `connected` event of the first packet (L69) is counted, not returned.
  int connected = 0;
  StreamItem next() {
    auto item = receiver->next(5000ms);
    if (item && std::holds_alternative<StreamEvent>(*item) &&
        std::get<StreamEvent>(*item).kind == StreamEventKind::connected) {
      ++connected;
      item = receiver->next(5000ms);
    }
    EXPECT_TRUE(item.has_value()) << "nothing arrived";
    return item.value_or(StreamItem{StreamEvent{}});
  }
  Sample next_sample() {
    StreamItem item = next();
    EXPECT_TRUE(std::holds_alternative<Sample>(item)) << std::get<StreamEvent>(item).message;
    return std::holds_alternative<Sample>(item) ? std::get<Sample>(item) : Sample{};
  }
  void skip_samples(std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) (void)next_sample();
  }
};

}  // namespace

// docs/conformance.md L69: the first packet brings the link up: `connected` comes ahead of
// its samples, once (the ULS and LS5 serial streams start the same way).
TEST(Ls5UdpReceiver, TheFirstPacketIsAnnouncedAsConnectedL69) {
  UdpRig rig;
  ASSERT_TRUE(rig.receiver && rig.sender);
  rig.send(build_packet(1));
  auto first = rig.receiver->next(5000ms);
  ASSERT_TRUE(first.has_value());
  ASSERT_TRUE(std::holds_alternative<StreamEvent>(*first));
  EXPECT_EQ(std::get<StreamEvent>(*first).kind, StreamEventKind::connected);
  EXPECT_EQ(std::get<StreamEvent>(*first).message.rfind("UDP packets from 127.0.0.1:", 0), 0U)
      << std::get<StreamEvent>(*first).message;
  rig.skip_samples(168);
  rig.send(build_packet(2));
  rig.skip_samples(168);  // no second `connected`
  EXPECT_EQ(rig.connected, 0);
}

// docs/conformance.md L45
TEST(Ls5UdpReceiver, RecordsBecomeSamplesWithFormula101) {
  UdpRig rig;
  ASSERT_TRUE(rig.receiver && rig.sender);
  Packet packet = build_packet(7);
  // Record 2: not measured yet (bit 0 clear); record 3: out of range (bit 2 clear).
  packet[2 * 3 + 2] = 0x02;
  packet[3 * 3 + 2] = 0x03;
  std::uint8_t checksum = 0;
  for (std::size_t i = 0; i < 510; ++i) checksum = static_cast<std::uint8_t>(checksum ^ packet[i]);
  packet[511] = checksum;
  rig.send(packet);
  const Sample first = rig.next_sample();
  EXPECT_EQ(first.device, "ls5");
  EXPECT_EQ(first.address, 1);
  EXPECT_EQ(first.get(ls5::channel::code), 0x2000);
  EXPECT_EQ(first.get(ls5::channel::signal), ls5::SignalState::ok);
  EXPECT_DOUBLE_EQ(first.get(ls5::channel::distance_mm).value_or(-1), 100.0 * 0x2000 / 0x4000);  // formula 10.1
  (void)rig.next_sample();
  const Sample unmeasured = rig.next_sample();
  EXPECT_EQ(unmeasured.get(ls5::channel::signal), ls5::SignalState::none_yet);
  EXPECT_FALSE(unmeasured.get(ls5::channel::distance_mm).has_value());
  const Sample out_of_range = rig.next_sample();
  EXPECT_EQ(out_of_range.get(ls5::channel::signal), ls5::SignalState::lost);
  EXPECT_FALSE(out_of_range.get(ls5::channel::distance_mm).has_value());
  rig.skip_samples(168 - 4);
  EXPECT_EQ(rig.receiver->counters().packets, 1U);
  EXPECT_EQ(rig.receiver->lost(), 0U);
}

// docs/conformance.md L46
TEST(Ls5UdpReceiver, ChecksumErrorsAreCountedAndReportedNotDecoded) {
  UdpRig rig;
  ASSERT_TRUE(rig.receiver && rig.sender);
  Packet bad = build_packet(1);
  bad[100] ^= 0x10;  // a bit flipped in transit
  rig.send(bad);
  StreamItem item = rig.next();
  ASSERT_TRUE(std::holds_alternative<StreamEvent>(item));
  EXPECT_EQ(std::get<StreamEvent>(item).kind, StreamEventKind::bad_frame);
  EXPECT_NE(std::get<StreamEvent>(item).message.find("checksum"), std::string::npos)
      << std::get<StreamEvent>(item).message;
  const std::array<std::uint8_t, 100> short_datagram{};
  rig.send_bytes(short_datagram);
  item = rig.next();
  ASSERT_TRUE(std::holds_alternative<StreamEvent>(item));
  EXPECT_EQ(std::get<StreamEvent>(item).kind, StreamEventKind::bad_frame);
  // The next good packet decodes (a changed counter byte is not part of the checksum).
  rig.send(build_packet(2));
  EXPECT_EQ(rig.next_sample().get(ls5::channel::code), 0x2000);
  EXPECT_EQ(rig.receiver->counters().bad_packets, 2U);
  EXPECT_EQ(rig.receiver->counters().packets, 1U);
}

TEST(Ls5UdpReceiver, CounterGapsAreLostRecordsAndTheWrapIsNotAGap) {
  UdpRig rig;
  ASSERT_TRUE(rig.receiver && rig.sender);
  rig.send(build_packet(254));
  rig.skip_samples(168);
  rig.send(build_packet(255));
  rig.skip_samples(168);
  rig.send(build_packet(0));  // 8-bit wrap: the next packet, nothing lost
  rig.skip_samples(168);
  rig.send(build_packet(3));  // 1 and 2 are missing
  StreamItem item = rig.next();
  ASSERT_TRUE(std::holds_alternative<StreamEvent>(item));
  const auto& event = std::get<StreamEvent>(item);
  EXPECT_EQ(event.kind, StreamEventKind::lost_records);
  EXPECT_EQ(event.count, 2U * 168U);
  rig.skip_samples(168);
  EXPECT_EQ(rig.receiver->counters().lost_packets, 2U);
  EXPECT_EQ(rig.receiver->lost(), 2U * 168U);
  EXPECT_EQ(rig.receiver->counters().packets, 4U);
}

// docs/conformance.md L65. §10.1: "The cyclic packet number counter is incremented when
// each packet is transmitted and is used to control the packet loss". The network
// delivered packet 11 twice: nothing was lost, and its 168 records are not new.
TEST(Ls5UdpReceiver, DuplicatedDatagramIsDroppedAndCountedNotLostL65) {
  UdpRig rig;
  ASSERT_TRUE(rig.receiver && rig.sender);
  rig.send(build_packet(11, 0x1000));
  rig.skip_samples(168);
  rig.send(build_packet(11, 0x1000));  // the same datagram again
  rig.send(build_packet(12, 0x3000));
  std::vector<StreamEvent> events;
  Sample next;
  for (;;) {
    StreamItem item = rig.next();
    if (const auto* sample = std::get_if<Sample>(&item)) {
      next = *sample;
      break;
    }
    events.push_back(std::get<StreamEvent>(item));
    if (events.size() > 5) break;
  }
  EXPECT_EQ(next.get(ls5::channel::code), 0x3000) << "the duplicate's records were emitted again";
  for (const auto& event : events) EXPECT_NE(event.kind, StreamEventKind::lost_records) << event.message;
  rig.skip_samples(167);
  EXPECT_EQ(rig.receiver->lost(), 0U);
  EXPECT_EQ(rig.receiver->counters().lost_packets, 0U);
  EXPECT_EQ(rig.receiver->counters().packets, 2U);
  EXPECT_EQ(rig.receiver->counters().duplicates, 1U);
  ASSERT_EQ(events.size(), 1U);
  EXPECT_NE(events[0].message.find("duplicate"), std::string::npos) << events[0].message;
}

// docs/conformance.md L63, L60, L87. Table 3.1: a 100 mm range has a discreteness of 0.001 mm,
// taken from the packet's range (§10.1 bytes 508-509). State bit 3: "the result corresponds to
// the distance derivative": kind derivative, valued by formula 8.2 scaled to 4000h (L87):
// "distance derivate = range · (code − 25000) / 50000" with 2000h for 25000 and 4000h for 50000.
TEST(Ls5UdpReceiver, SamplesCarryTheDiscretenessAndMarkDerivativesL63) {
  UdpRig rig;
  ASSERT_TRUE(rig.receiver && rig.sender);
  rig.send(build_packet(1, 0x2000, 0x07));
  const Sample distance = rig.next_sample();
  EXPECT_EQ(distance.kind, ls5::kind::result);
  EXPECT_EQ(distance.get(ls5::channel::resolution_mm), 0.001);
  rig.skip_samples(167);
  rig.send(build_packet(2, 0x2000, 0x0F));  // measured, bit 1, in range, derivative
  const Sample derivative = rig.next_sample();
  EXPECT_EQ(derivative.kind, ls5::kind::derivative);
  EXPECT_EQ(derivative.get(ls5::channel::signal), ls5::SignalState::ok);
  EXPECT_FALSE(derivative.get(ls5::channel::distance_mm).has_value());
  EXPECT_DOUBLE_EQ(derivative.get(ls5::channel::derivative_mm).value_or(-1), 0.0);  // 2000h: no change
  rig.skip_samples(167);
  rig.send(build_packet(3, 0x2800, 0x0F));
  EXPECT_DOUBLE_EQ(rig.next_sample().get(ls5::channel::derivative_mm).value_or(-1), 12.5);  // 100 × 800h / 4000h
  rig.skip_samples(167);
}

// docs/conformance.md L85. §10.1: "The state of bit 1 is always "1"", "The remaining bits of
// the status word are reserved and are always "0" when read." One record whose word has
// reserved bit 4 set (0x17) is kept in its place as a suspect sample naming the word, with no
// signal and no value; the other 167 of its packet are ordinary samples.
TEST(Ls5UdpReceiver, ABadStateWordFlagsItsRecordAndKeepsTheOther167L85) {
  UdpRig rig;
  ASSERT_TRUE(rig.receiver && rig.sender);
  Packet packet = build_packet(1, 0x2000, 0x07);
  packet[4 * 3 + 2] = 0x17;                                            // measurement 5
  packet[511] = static_cast<std::uint8_t>(packet[511] ^ 0x07 ^ 0x17);  // the checksum follows the byte
  rig.send(packet);
  for (int i = 0; i < 168; ++i) {
    const Sample sample = rig.next_sample();
    EXPECT_EQ(sample.get(ls5::channel::code), 0x2000) << i;
    if (i == 4) {
      EXPECT_TRUE(sample.suspect);
      EXPECT_NE(sample.suspect_reason.find("measurement 5"), std::string::npos) << sample.suspect_reason;
      EXPECT_NE(sample.suspect_reason.find("0x17"), std::string::npos) << sample.suspect_reason;
      EXPECT_NE(sample.suspect_reason.find("bits 4-7"), std::string::npos) << sample.suspect_reason;
      EXPECT_FALSE(sample.get(ls5::channel::signal).has_value());
      EXPECT_FALSE(sample.get(ls5::channel::distance_mm).has_value());
    } else {
      EXPECT_FALSE(sample.suspect) << i << ": " << sample.suspect_reason;
      EXPECT_EQ(sample.get(ls5::channel::signal), ls5::SignalState::ok) << i;
      EXPECT_DOUBLE_EQ(sample.get(ls5::channel::distance_mm).value_or(-1), 50.0) << i;  // 100 × 2000h / 4000h
    }
  }
  const auto counters = rig.receiver->counters();
  EXPECT_EQ(counters.packets, 1U);
  EXPECT_EQ(counters.bad_packets, 0U);
  EXPECT_EQ(counters.suspect_records, 1U);
}

// docs/conformance.md L86. §10.1: "The measurement result is passed as a two-byte number in
// the code from 0 to 4000h." 4001h with the in-range bit set is past the end of the range:
// signal lost (out of range), flagged suspect with the reason, no distance.
TEST(Ls5UdpReceiver, ACodeAbove4000hIsOutOfRangeL86) {
  UdpRig rig;
  ASSERT_TRUE(rig.receiver && rig.sender);
  rig.send(build_packet(1, 0x4001, 0x07));
  const Sample past = rig.next_sample();
  EXPECT_EQ(past.get(ls5::channel::code), 0x4001);
  EXPECT_EQ(past.get(ls5::channel::signal), ls5::SignalState::lost);
  EXPECT_FALSE(past.get(ls5::channel::distance_mm).has_value());
  EXPECT_TRUE(past.suspect);
  EXPECT_NE(past.suspect_reason.find("above 0x4000"), std::string::npos) << past.suspect_reason;
  rig.skip_samples(167);
  rig.send(build_packet(2, 0x4000, 0x07));  // 4000h itself is the end of the range: 100 mm
  const Sample end = rig.next_sample();
  EXPECT_EQ(end.get(ls5::channel::signal), ls5::SignalState::ok);
  EXPECT_FALSE(end.suspect);
  EXPECT_DOUBLE_EQ(end.get(ls5::channel::distance_mm).value_or(-1), 100.0);
  rig.skip_samples(167);
  EXPECT_EQ(rig.receiver->counters().suspect_records, 168U);
}
