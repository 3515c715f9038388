// The §10.1 reader, what the service's UDP listener runs on every datagram from the network:
// the input cut into datagrams (each a length byte pair, then its bytes), read one after
// another so the counter is followed across them. A datagram the codec accepts gives its
// 168 samples; every item is a sample or an event; the counters add up.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "rangekit/ls5/udp_packet.hpp"
#include "rangekit/ls5/udp_packet_reader.hpp"

using namespace rangekit;
using namespace rangekit::ls5;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  UdpPacketReader reader(7);
  const Endpoint from{"192.0.2.1", 6030};
  std::vector<StreamItem> items;
  std::uint64_t decoded = 0;
  std::uint64_t samples = 0;
  for (std::size_t at = 0; at + 2 <= size;) {
    const std::size_t length = (std::size_t{data[at]} << 8 | data[at + 1]) % 1024;
    at += 2;
    const std::size_t taken = length < size - at ? length : size - at;
    const Bytes datagram(data + at, taken);
    at += taken;
    const bool valid = decode_udp_packet(datagram).ok();
    items.clear();
    reader.read(datagram, from, items);
    std::size_t here = 0;
    for (const StreamItem& item : items) {
      if (const auto* sample = std::get_if<Sample>(&item)) {
        ++here;
        if (sample->address != 7) std::abort();
      }
    }
    if (!valid && here != 0) std::abort();
    if (here != 0 && here != udp_record_count) std::abort();
    decoded += here != 0 ? 1 : 0;
    samples += here;
  }
  const UdpPacketCounters counters = reader.counters();
  if (counters.packets != decoded || samples != decoded * udp_record_count) std::abort();
  if (counters.lost_records != counters.lost_packets * udp_record_count) std::abort();
  return 0;
}
