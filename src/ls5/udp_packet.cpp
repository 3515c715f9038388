#include "rangekit/ls5/udp_packet.hpp"

#include <cstring>
#include <string>

#include "ls5/messages.hpp"

namespace rangekit::ls5 {
namespace {

constexpr std::size_t record_size = 3;
static_assert(udp_record_count * record_size == udp_offset::serial, "records fill bytes 0-503");

std::uint16_t read_le16(Bytes bytes, std::size_t at) noexcept {
  return static_cast<std::uint16_t>(bytes[at] | (bytes[at + 1] << 8U));
}

void write_le16(std::span<std::uint8_t, udp_packet_size> out, std::size_t at, std::uint16_t value) noexcept {
  out[at] = static_cast<std::uint8_t>(value & 0xFFU);
  out[at + 1] = static_cast<std::uint8_t>(value >> 8U);
}

bool valid_state(std::uint8_t state) noexcept {
  return (state & udp_state::always_one) != 0 && (state & udp_state::reserved) == 0;
}

const char* state_problem(std::uint8_t state) {
  return (state & udp_state::always_one) == 0 ? "bit 1 must always be 1" : "bits 4-7 are reserved and must be 0";
}

Error state_error(std::size_t record, std::uint8_t state) {
  return make_error(Errc::invalid_frame, "LS5 UDP packet: state word 0x" + text::hex_byte(state) + " of measurement " +
                                             std::to_string(record + 1) + ": " + state_problem(state));
}

// What formulas 10.1 and 8.2 need of a record: a valid state word, measured, in range, code 0-0x4000.
Status check_convertible(const UdpRecord& record) {
  if (auto state = check_udp_state(record.state); !state) return state;
  if (!record.measured()) return make_error(Errc::out_of_range, "LS5 UDP record: no measurement yet (state bit 0)");
  if (!record.in_range()) return make_error(Errc::out_of_range, "LS5 UDP record: out of range (state bit 2)");
  if (record.code > udp_full_scale_code) {
    return make_error(Errc::out_of_range,
                      "LS5 UDP record code " + std::to_string(record.code) + " is above 0x4000, the full range");
  }
  return ok_status();
}

// Eight bytes at a time, folded to one at the end: a byte at a time ran at a
// twentieth of a plain XOR pass.
std::uint8_t xor_of(Bytes bytes) noexcept {
  std::uint64_t folded = 0;
  std::size_t at = 0;
  for (; at + sizeof folded <= bytes.size(); at += sizeof folded) {
    std::uint64_t word = 0;
    std::memcpy(&word, bytes.data() + at, sizeof word);
    folded ^= word;
  }
  folded ^= folded >> 32U;
  folded ^= folded >> 16U;
  folded ^= folded >> 8U;
  auto sum = static_cast<std::uint8_t>(folded);
  for (; at < bytes.size(); ++at) sum = static_cast<std::uint8_t>(sum ^ bytes[at]);
  return sum;
}

}  // namespace

Status check_udp_state(std::uint8_t state) {
  if (valid_state(state)) return ok_status();
  return make_error(Errc::invalid_frame, "LS5 UDP state word 0x" + text::hex_byte(state) + ": " + state_problem(state));
}

std::uint8_t udp_checksum(std::span<const std::uint8_t, udp_packet_size> datagram) noexcept {
  return xor_of(datagram.first(udp_offset::counter));
}

Result<UdpPacket> decode_udp_packet(Bytes datagram) {
  if (datagram.size() != udp_packet_size) {
    return make_error(datagram.size() < udp_packet_size ? Errc::truncated : Errc::overlong,
                      "LS5 UDP packet has " + std::to_string(datagram.size()) + " bytes, expected 512");
  }
  const std::uint8_t computed = xor_of(datagram.first(udp_offset::counter));
  if (computed != datagram[udp_offset::checksum]) {
    return make_error(Errc::bad_checksum, "LS5 UDP packet: checksum byte 0x" +
                                              text::hex_byte(datagram[udp_offset::checksum]) +
                                              ", the XOR of bytes 0-509 is 0x" + text::hex_byte(computed));
  }
  // State words are not checked here: a record whose word is not as documented is the
  // caller's to flag, the packet's other records stay good (L85).
  UdpPacket packet;
  for (std::size_t i = 0; i < udp_record_count; ++i) {
    const std::size_t at = i * record_size;
    packet.records[i] = UdpRecord{read_le16(datagram, at), datagram[at + 2]};
  }
  packet.serial_number = read_le16(datagram, udp_offset::serial);
  packet.lower_boundary_mm = read_le16(datagram, udp_offset::lower_boundary);
  packet.range_mm = read_le16(datagram, udp_offset::range);
  packet.counter = datagram[udp_offset::counter];
  return packet;
}

Status encode_udp_packet(const UdpPacket& packet, std::span<std::uint8_t, udp_packet_size> out) {
  for (std::size_t i = 0; i < udp_record_count; ++i) {
    if (!valid_state(packet.records[i].state)) return state_error(i, packet.records[i].state);
  }
  for (std::size_t i = 0; i < udp_record_count; ++i) {
    write_le16(out, i * record_size, packet.records[i].code);
    out[i * record_size + 2] = packet.records[i].state;
  }
  write_le16(out, udp_offset::serial, packet.serial_number);
  write_le16(out, udp_offset::lower_boundary, packet.lower_boundary_mm);
  write_le16(out, udp_offset::range, packet.range_mm);
  out[udp_offset::counter] = packet.counter;
  out[udp_offset::checksum] = udp_checksum(out);
  return ok_status();
}

Result<double> udp_distance_mm(const UdpRecord& record, double range_mm) {
  if (auto convertible = check_convertible(record); !convertible) return convertible.error();
  if (record.derivative()) {
    return make_error(Errc::unsupported,
                      "LS5 UDP record holds a derivative (state bit 3): a change, not a distance (udp_derivative_mm)");
  }
  return range_mm * record.code / udp_full_scale_code;
}

Result<double> udp_derivative_mm(const UdpRecord& record, double range_mm) {
  if (auto convertible = check_convertible(record); !convertible) return convertible.error();
  if (!record.derivative()) {
    return make_error(Errc::unsupported, "LS5 UDP record holds a distance (state bit 3 clear), not a derivative");
  }
  return range_mm * (static_cast<double>(record.code) - udp_derivative_zero_code) / udp_full_scale_code;
}

std::uint8_t udp_packets_lost(std::uint8_t previous_counter, std::uint8_t counter) noexcept {
  if (udp_packet_is_duplicate(previous_counter, counter)) return 0;
  return static_cast<std::uint8_t>(counter - previous_counter - 1);
}

}  // namespace rangekit::ls5
