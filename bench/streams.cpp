#include "streams.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <random>

#include "rangekit/ls5/udp_packet.hpp"

namespace rangekit::bench {

std::string uls_binning_stream(std::size_t bytes, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> targets(1, 15);
  std::uniform_real_distribution<double> distance(0.15, 1664.0);
  std::uniform_int_distribution<int> strength(1, 999);
  std::uniform_int_distribution<int> error_roll(0, 99);
  std::string stream;
  stream.reserve(bytes + 64);
  char line[64];
  while (stream.size() < bytes) {
    if (error_roll(random) == 0) {
      stream += "$ER,4\r";
      continue;
    }
    const int count = targets(random);
    for (int i = 0; i < count; ++i) {
      const int length =
          std::snprintf(line, sizeof line, "$BM,%d,%d,%.3f,%d\r", i, count, distance(random), strength(random));
      stream.append(line, static_cast<std::size_t>(length));
    }
  }
  return stream;
}

std::string uls_averaging_stream(std::size_t bytes, std::uint32_t seed, bool with_intensity) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> distance(0.15, 1664.0);
  std::uniform_int_distribution<int> width(1000, 9999999);
  std::uniform_int_distribution<int> error_roll(0, 99);
  std::string stream;
  stream.reserve(bytes + 64);
  char line[64];
  while (stream.size() < bytes) {
    if (error_roll(random) == 0) {
      stream += "$ER,4\r";
      continue;
    }
    const int length = with_intensity
                           ? std::snprintf(line, sizeof line, "$BM,%.3f,%d\r", distance(random), width(random))
                           : std::snprintf(line, sizeof line, "$BM,%.3f\r", distance(random));
    stream.append(line, static_cast<std::size_t>(length));
  }
  return stream;
}

std::string ls5_udp_stream(std::size_t bytes, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> step(0.0, 40.0);
  std::string stream;
  stream.reserve(bytes + ls5::udp_packet_size);
  double code = 8000.0;
  ls5::UdpPacket packet;
  packet.serial_number = 157;
  packet.lower_boundary_mm = 8;
  packet.range_mm = 40;
  std::array<std::uint8_t, ls5::udp_packet_size> datagram{};
  while (stream.size() < bytes) {
    for (auto& record : packet.records) {
      code = std::clamp(code + step(random), 0.0, 16384.0);
      record = ls5::UdpRecord{static_cast<std::uint16_t>(code), 0x07};
    }
    ++packet.counter;
    (void)ls5::encode_udp_packet(packet, datagram);
    stream.append(reinterpret_cast<const char*>(datagram.data()), datagram.size());
  }
  return stream;
}

std::string ls5_stream(std::size_t bytes, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> step(0.0, 40.0);
  std::uniform_int_distribution<int> dropout(0, 199);
  std::string stream;
  stream.reserve(bytes + 8);
  double code = 25000.0;
  char line[16];
  while (stream.size() < bytes) {
    code += step(random);
    if (code < 0) code = 0;
    if (code > 50000) code = 50000;
    const unsigned value = dropout(random) == 0 ? 65535U : static_cast<unsigned>(code);
    const int length = std::snprintf(line, sizeof line, "!%05u\r", value);
    stream.append(line, static_cast<std::size_t>(length));
  }
  return stream;
}

}  // namespace rangekit::bench
