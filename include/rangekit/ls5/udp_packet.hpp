// The Ethernet measurement datagram (§10.1, conformance L12): 512 bytes holding
// 168 records of (code low, code high, state), the sensor's serial number, lower
// boundary and range, a cyclic counter and an XOR checksum.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "rangekit/core/framer.hpp"
#include "rangekit/core/result.hpp"

namespace rangekit::ls5 {

inline constexpr std::size_t udp_packet_size = 512;
inline constexpr std::size_t udp_record_count = 168;
inline constexpr std::uint16_t udp_full_scale_code = 0x4000;  // formula 10.1
// The derivative's zero: formula 8.2's 25000 of 50000, scaled to 0x4000 as 10.1 scales 8.1 (L87).
inline constexpr std::uint16_t udp_derivative_zero_code = 0x2000;

namespace udp_offset {
inline constexpr std::size_t serial = 504;
inline constexpr std::size_t lower_boundary = 506;
inline constexpr std::size_t range = 508;
inline constexpr std::size_t counter = 510;
inline constexpr std::size_t checksum = 511;
}  // namespace udp_offset

namespace udp_state {
inline constexpr std::uint8_t measured = 0x01;    // bit 0: a measurement has been made
inline constexpr std::uint8_t always_one = 0x02;  // bit 1
inline constexpr std::uint8_t in_range = 0x04;    // bit 2: 0 means "OUT OF RANGE"
inline constexpr std::uint8_t derivative = 0x08;  // bit 3: the code is a distance derivative
inline constexpr std::uint8_t reserved = 0xF0;    // bits 4-7: always 0
}  // namespace udp_state

struct UdpRecord {
  std::uint16_t code = 0;
  std::uint8_t state = udp_state::always_one;

  [[nodiscard]] constexpr bool measured() const noexcept { return (state & udp_state::measured) != 0; }
  [[nodiscard]] constexpr bool in_range() const noexcept { return (state & udp_state::in_range) != 0; }
  [[nodiscard]] constexpr bool derivative() const noexcept { return (state & udp_state::derivative) != 0; }
  friend constexpr bool operator==(const UdpRecord&, const UdpRecord&) = default;
};

struct UdpPacket {
  std::array<UdpRecord, udp_record_count> records{};
  std::uint16_t serial_number = 0;
  std::uint16_t lower_boundary_mm = 0;  // whole millimetres (L12)
  std::uint16_t range_mm = 0;
  std::uint8_t counter = 0;
  friend bool operator==(const UdpPacket&, const UdpPacket&) = default;
};

// XOR of bytes 0-509: every byte but the counter and the checksum (L12).
std::uint8_t udp_checksum(std::span<const std::uint8_t, udp_packet_size> datagram) noexcept;

// Whether a state word reads as §10.1 describes it: bit 1 set, reserved bits 4-7 clear. The
// error names what is wrong.
Status check_udp_state(std::uint8_t state);

// Checks size and checksum. Every record is kept as sent, also one whose state word
// check_udp_state refuses: one bad record does not cost the other 167 (L85).
Result<UdpPacket> decode_udp_packet(Bytes datagram);
// Writes the datagram with its checksum; rejects records with invalid state bits.
Status encode_udp_packet(const UdpPacket& packet, std::span<std::uint8_t, udp_packet_size> out);

// Formula 10.1: range × code / 0x4000, for a measured, in-range, pure-distance
// record with a valid state word and code 0-0x4000 (conformance L19).
Result<double> udp_distance_mm(const UdpRecord& record, double range_mm);
// Formula 8.2 scaled to the UDP code: range × (code − 0x2000) / 0x4000, for a measured,
// in-range derivative record with a valid state word and code 0-0x4000 (L87).
Result<double> udp_derivative_mm(const UdpRecord& record, double range_mm);

// A counter equal to the previous packet's: the same packet again (a duplicated
// datagram), to be dropped, not 255 lost packets (conformance L19).
constexpr bool udp_packet_is_duplicate(std::uint8_t previous_counter, std::uint8_t counter) noexcept {
  return counter == previous_counter;
}
// Packets lost between two consecutive counters, 8-bit wrap: 255 -> 1 is 1 lost.
// A duplicate (equal counters) loses nothing: 0.
std::uint8_t udp_packets_lost(std::uint8_t previous_counter, std::uint8_t counter) noexcept;

}  // namespace rangekit::ls5
