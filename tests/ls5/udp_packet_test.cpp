// §10.1 UDP data packet, conformance L12, L19, L85 and L87. The packet is built by hand
// here and its checksum worked out by hand, not by the code under test.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "rangekit/ls5/udp_packet.hpp"

using namespace rangekit;
using namespace rangekit::ls5;

namespace {

// 168 records with state 0x02 (bit 1 "always 1", not yet measured, code 0), then:
//   record 1: code 0x2000 (bytes 00 20), state 0x07 (measured, bit 1, in range)
//   record 2: code 0x4000 (bytes 00 40), state 0x07
//   serial 157 = 0x009D (9D 00), lower boundary 8 mm (08 00), range 40 mm (28 00)
//   counter 0x05, checksum 0xDD.
// Checksum by hand: the 166 plain records give 0x02 an even number of times = 0x00;
// record 1: 00^20^07 = 0x27; record 2: 00^40^07 = 0x47; 0x27^0x47 = 0x60;
// ^9D = 0xFD; ^00 = 0xFD; ^08 = 0xF5; ^00; ^28 = 0xDD; ^00 = 0xDD. Counter excluded.
std::vector<std::uint8_t> hand_made_packet() {
  std::vector<std::uint8_t> packet(512, 0x00);
  for (std::size_t record = 0; record < 168; ++record) packet[record * 3 + 2] = 0x02;
  packet[0] = 0x00;
  packet[1] = 0x20;
  packet[2] = 0x07;
  packet[3] = 0x00;
  packet[4] = 0x40;
  packet[5] = 0x07;
  packet[504] = 0x9D;
  packet[505] = 0x00;
  packet[506] = 0x08;
  packet[507] = 0x00;
  packet[508] = 0x28;
  packet[509] = 0x00;
  packet[510] = 0x05;
  packet[511] = 0xDD;
  return packet;
}

}  // namespace

TEST(Ls5UdpPacket, HandMadePacketDecodesL12) {
  const auto bytes = hand_made_packet();
  const auto packet = decode_udp_packet(bytes);
  ASSERT_TRUE(packet.ok()) << packet.error().describe();
  EXPECT_EQ(packet->records[0].code, 0x2000);
  EXPECT_EQ(packet->records[0].state, 0x07);
  EXPECT_TRUE(packet->records[0].measured());
  EXPECT_TRUE(packet->records[0].in_range());
  EXPECT_FALSE(packet->records[0].derivative());
  EXPECT_EQ(packet->records[1].code, 0x4000);
  EXPECT_EQ(packet->records[2].code, 0);
  EXPECT_FALSE(packet->records[2].measured());
  EXPECT_EQ(packet->records[167].state, 0x02);
  EXPECT_EQ(packet->serial_number, 157);
  EXPECT_EQ(packet->lower_boundary_mm, 8);
  EXPECT_EQ(packet->range_mm, 40);
  EXPECT_EQ(packet->counter, 5);
  EXPECT_EQ(udp_checksum(std::span<const std::uint8_t, 512>(bytes.data(), 512)), 0xDD);
}

TEST(Ls5UdpPacket, DistanceFormula101) {
  const auto bytes = hand_made_packet();
  const auto packet = decode_udp_packet(bytes);
  ASSERT_TRUE(packet.ok());
  // 40 × 0x2000 / 0x4000 = 20 mm; 40 × 0x4000 / 0x4000 = 40 mm.
  EXPECT_DOUBLE_EQ(udp_distance_mm(packet->records[0], packet->range_mm).value_or(-1), 20.0);
  EXPECT_DOUBLE_EQ(udp_distance_mm(packet->records[1], packet->range_mm).value_or(-1), 40.0);
  // 100 × 0x1000 / 0x4000 = 25 mm.
  EXPECT_DOUBLE_EQ(udp_distance_mm(UdpRecord{0x1000, 0x07}, 100.0).value_or(-1), 25.0);
}

TEST(Ls5UdpPacket, DistanceNeedsAMeasuredInRangeRecordL19) {
  EXPECT_EQ(udp_distance_mm(UdpRecord{0x2000, 0x02}, 40.0).error().code, Errc::out_of_range);  // not measured
  const auto out = udp_distance_mm(UdpRecord{0x2000, 0x03}, 40.0);                             // bit 2 clear
  ASSERT_FALSE(out.ok());
  EXPECT_NE(out.error().message.find("out of range"), std::string::npos);
  EXPECT_EQ(udp_distance_mm(UdpRecord{0x2000, 0x0F}, 40.0).error().code, Errc::unsupported);  // derivative
  // §10.1 "a two-byte number in the code from 0 to 4000h": 4001h is past the range (L86).
  EXPECT_EQ(udp_distance_mm(UdpRecord{0x4001, 0x07}, 40.0).error().code, Errc::out_of_range);
}

TEST(Ls5UdpPacket, EveryByteButTheCounterIsCoveredL12) {
  const auto good = hand_made_packet();
  for (std::size_t i = 0; i < 512; ++i) {
    auto flipped = good;
    // State words get bit 0 flipped, which keeps them legal, so that only the
    // checksum can notice; every other byte gets bit 4 flipped.
    const bool state_byte = i < 504 && i % 3 == 2;
    flipped[i] = static_cast<std::uint8_t>(flipped[i] ^ (state_byte ? 0x01 : 0x10));
    const auto packet = decode_udp_packet(flipped);
    if (i == 510) {
      ASSERT_TRUE(packet.ok()) << "counter change must not affect the checksum";
      EXPECT_EQ(packet->counter, 0x05 ^ 0x10);
    } else {
      ASSERT_FALSE(packet.ok()) << "byte " << i;
      EXPECT_EQ(packet.error().code, Errc::bad_checksum) << "byte " << i;
    }
  }
}

TEST(Ls5UdpPacket, WrongSizeL12) {
  auto bytes = hand_made_packet();
  const auto short_packet = decode_udp_packet(Bytes(bytes.data(), 511));
  ASSERT_FALSE(short_packet.ok());
  EXPECT_EQ(short_packet.error().code, Errc::truncated);
  EXPECT_EQ(short_packet.error().message, "LS5 UDP packet has 511 bytes, expected 512");
  bytes.push_back(0x00);
  const auto long_packet = decode_udp_packet(bytes);
  ASSERT_FALSE(long_packet.ok());
  EXPECT_EQ(long_packet.error().code, Errc::overlong);
  EXPECT_FALSE(decode_udp_packet(Bytes{}).ok());
}

// L85. §10.1: "The state of bit 1 is always "1"", "The remaining bits of the status word are
// reserved and are always "0" when read." A record whose word breaks that is kept, for the
// caller to flag; the packet and its other records decode.
TEST(Ls5UdpPacket, ABadStateWordKeepsThePacketAndNamesItsProblemL85) {
  // Record 3's state 0x02 → 0x00 (bit 1 clear); fix the checksum by hand: 0xDD ^ 0x02 = 0xDF.
  auto bytes = hand_made_packet();
  bytes[8] = 0x00;
  bytes[511] = 0xDF;
  const auto cleared = decode_udp_packet(bytes);
  ASSERT_TRUE(cleared.ok()) << cleared.error().message;
  EXPECT_EQ(cleared->records[2].state, 0x00);
  const Status bit_1 = check_udp_state(cleared->records[2].state);
  ASSERT_FALSE(bit_1.ok());
  EXPECT_EQ(bit_1.error().code, Errc::invalid_frame);
  EXPECT_NE(bit_1.error().message.find("bit 1"), std::string::npos) << bit_1.error().message;
  EXPECT_DOUBLE_EQ(udp_distance_mm(cleared->records[0], cleared->range_mm).value_or(-1), 20.0);  // 40 × 1/2
  EXPECT_EQ(udp_distance_mm(cleared->records[2], cleared->range_mm).error().code, Errc::invalid_frame);

  // Record 168's state 0x02 → 0x12 (reserved bit 4); checksum 0xDD ^ 0x10 = 0xCD.
  bytes = hand_made_packet();
  bytes[503] = 0x12;
  bytes[511] = 0xCD;
  const auto reserved = decode_udp_packet(bytes);
  ASSERT_TRUE(reserved.ok()) << reserved.error().message;
  const Status bits_4_to_7 = check_udp_state(reserved->records[167].state);
  ASSERT_FALSE(bits_4_to_7.ok());
  EXPECT_NE(bits_4_to_7.error().message.find("bits 4-7"), std::string::npos) << bits_4_to_7.error().message;
  EXPECT_TRUE(check_udp_state(reserved->records[166].state).ok());
  // A record with a measured, in-range word of 0x17 (bit 4 set) gives no distance either.
  EXPECT_EQ(udp_distance_mm(UdpRecord{0x2000, 0x17}, 40.0).error().code, Errc::invalid_frame);
}

// L87. §8.9: for a derivative "The number 0 corresponds to the minimum value of the derivative,
// the number 50000 - the maximum value of the derivative, and the number 25000 - the zero value",
// distance derivate = range · (code − 25000) / 50000 (8.2); §10.1 scales 0...50000 to 0...4000h
// (formula 10.1 against 8.1), so 2000h is the zero: range · (code − 2000h) / 4000h.
TEST(Ls5UdpPacket, DerivativeRecordsFollowFormula82ScaledTo4000hL87) {
  EXPECT_DOUBLE_EQ(udp_derivative_mm(UdpRecord{0x2000, 0x0F}, 40.0).value_or(-1), 0.0);
  EXPECT_DOUBLE_EQ(udp_derivative_mm(UdpRecord{0x2800, 0x0F}, 40.0).value_or(-1), 5.0);  // 40 × 800h / 4000h
  EXPECT_DOUBLE_EQ(udp_derivative_mm(UdpRecord{0x1000, 0x0F}, 100.0).value_or(0), -25.0);
  EXPECT_DOUBLE_EQ(udp_derivative_mm(UdpRecord{0x4000, 0x0F}, 40.0).value_or(-1), 20.0);         // the maximum
  EXPECT_DOUBLE_EQ(udp_derivative_mm(UdpRecord{0x0000, 0x0F}, 40.0).value_or(0), -20.0);         // the minimum
  EXPECT_EQ(udp_derivative_mm(UdpRecord{0x2000, 0x07}, 40.0).error().code, Errc::unsupported);   // a distance
  EXPECT_EQ(udp_derivative_mm(UdpRecord{0x2000, 0x0B}, 40.0).error().code, Errc::out_of_range);  // bit 2 clear
  EXPECT_EQ(udp_derivative_mm(UdpRecord{0x4001, 0x0F}, 40.0).error().code, Errc::out_of_range);
}

TEST(Ls5UdpPacket, EncodeMatchesTheHandMadeBytes) {
  UdpPacket packet;  // every record defaults to code 0, state 0x02
  packet.records[0] = UdpRecord{0x2000, 0x07};
  packet.records[1] = UdpRecord{0x4000, 0x07};
  packet.serial_number = 157;
  packet.lower_boundary_mm = 8;
  packet.range_mm = 40;
  packet.counter = 5;
  std::array<std::uint8_t, 512> out{};
  ASSERT_TRUE(encode_udp_packet(packet, out).ok());
  const auto expected = hand_made_packet();
  EXPECT_TRUE(std::equal(out.begin(), out.end(), expected.begin()));

  const auto decoded = decode_udp_packet(out);
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(*decoded, packet);

  packet.records[7].state = 0x22;
  EXPECT_FALSE(encode_udp_packet(packet, out).ok());
}

TEST(Ls5UdpPacket, CounterGapWithWrapL12) {
  EXPECT_EQ(udp_packets_lost(4, 5), 0);
  EXPECT_EQ(udp_packets_lost(4, 7), 2);
  EXPECT_EQ(udp_packets_lost(255, 0), 0);
  EXPECT_EQ(udp_packets_lost(255, 1), 1);  // 0 was lost
  EXPECT_EQ(udp_packets_lost(250, 3), 8);  // 251..255, 0, 1, 2
}

// L19: §10.1 "The cyclic packet number counter is incremented when each packet is
// transmitted and is used to control the packet loss": a counter that did not move
// means no packet was transmitted in between, so it is the same packet again.
TEST(Ls5UdpPacket, RepeatedCounterIsADuplicateNotALossL19) {
  EXPECT_TRUE(udp_packet_is_duplicate(11, 11));
  EXPECT_EQ(udp_packets_lost(11, 11), 0);
  EXPECT_FALSE(udp_packet_is_duplicate(11, 12));
  EXPECT_FALSE(udp_packet_is_duplicate(255, 0));
}
