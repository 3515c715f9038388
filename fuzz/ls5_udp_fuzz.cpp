// The §10.1 UDP packet decoder on arbitrary datagrams; what decodes must encode
// back to the same 512 bytes and decode to the same packet.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "rangekit/ls5/udp_packet.hpp"

using namespace rangekit;
using namespace rangekit::ls5;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto packet = decode_udp_packet(Bytes(data, size));
  if (!packet.ok()) return 0;
  if (size != udp_packet_size) std::abort();
  std::array<std::uint8_t, udp_packet_size> encoded{};
  if (!encode_udp_packet(*packet, encoded).ok()) std::abort();
  if (std::memcmp(encoded.data(), data, udp_packet_size) != 0) std::abort();
  const auto again = decode_udp_packet(encoded);
  if (!again.ok() || !(*again == *packet)) std::abort();
  for (const UdpRecord& record : packet->records) {
    const auto distance = udp_distance_mm(record, packet->range_mm);
    if (distance.ok() && (*distance < 0.0 || *distance > packet->range_mm)) std::abort();
  }
  return 0;
}
