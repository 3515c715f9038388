// The site bench's load rig (bench/site_scale_bench.cpp, docs/performance.md "A site on one
// box"): the §10.1 datagrams of N LS5 sensors at R results a second each, sent on loopback
// from one thread on absolute deadlines, so that what is measured is the service and not the
// sender. Sensor i sends to FIRST_PORT + i; its packets start i/N of a packet period after
// sensor 0's, so the load is spread evenly over time.
//
// Each record's code says where it came from: (packet % 97) x 168 + record, and the range is
// 16384 mm, so a distance reads as its code in millimetres (formula 10.1). When it ends
// (SIGTERM, SIGINT or --seconds), it writes one line per packet sent to --log:
// "SENSOR PACKET NANOSECONDS" on the monotonic clock (std::chrono::steady_clock), for latencies.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>
#include <string_view>
#include <vector>

#include "rangekit/ls5/udp_packet.hpp"

namespace {

using Clock = std::chrono::steady_clock;

constexpr std::uint16_t range_mm = 16384;    // a code reads as millimetres
constexpr std::uint32_t packet_labels = 97;  // 97 x 168 = 16296 codes, below 0x4000

std::atomic<bool> stopping{false};

void on_signal(int /*signal*/) { stopping = true; }

struct Options {
  std::string host = "127.0.0.1";
  int first_port = 0;
  int sensors = 0;
  double rate_hz = 1000;
  double seconds = 0;  // 0: until a signal
  std::string log;
};

bool parse(int argc, char** argv, Options& options) {
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string_view key = argv[i];
    const char* value = argv[i + 1];
    if (key == "--host") {
      options.host = value;
    } else if (key == "--first-port") {
      options.first_port = std::atoi(value);
    } else if (key == "--sensors") {
      options.sensors = std::atoi(value);
    } else if (key == "--rate-hz") {
      options.rate_hz = std::atof(value);
    } else if (key == "--seconds") {
      options.seconds = std::atof(value);
    } else if (key == "--log") {
      options.log = value;
    } else {
      std::fprintf(stderr, "udp_pacer: unknown option %s\n", argv[i]);
      return false;
    }
  }
  if ((argc - 1) % 2 != 0 || options.first_port <= 0 || options.first_port + options.sensors > 65535 ||
      options.sensors <= 0 || options.rate_hz <= 0) {
    std::fprintf(stderr,
                 "usage: udp_pacer --first-port PORT --sensors N [--host IP] [--rate-hz 1000] [--seconds S] "
                 "[--log FILE]\n");
    return false;
  }
  return true;
}

// The datagram of `sensor`'s packet number `packet`.
void fill(std::array<std::uint8_t, rangekit::ls5::udp_packet_size>& datagram, int sensor, std::uint32_t packet) {
  namespace ls5 = rangekit::ls5;
  ls5::UdpPacket content;
  const auto label = static_cast<std::uint16_t>((packet % packet_labels) * ls5::udp_record_count);
  for (std::size_t i = 0; i < ls5::udp_record_count; ++i) {
    content.records[i].code = static_cast<std::uint16_t>(label + i);
    content.records[i].state = ls5::udp_state::always_one | ls5::udp_state::measured | ls5::udp_state::in_range;
  }
  content.serial_number = static_cast<std::uint16_t>(sensor);
  content.range_mm = range_mm;
  content.counter = static_cast<std::uint8_t>(packet);
  (void)ls5::encode_udp_packet(content, datagram);
}

struct Sent {
  int sensor = 0;
  std::uint32_t packet = 0;
  std::int64_t at_ns = 0;
};

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parse(argc, argv, options)) return 2;
  const int sock = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (sock < 0) {
    std::perror("udp_pacer: socket");
    return 1;
  }
  sockaddr_in to{};
  to.sin_family = AF_INET;
  if (::inet_pton(AF_INET, options.host.c_str(), &to.sin_addr) != 1) {
    std::fprintf(stderr, "udp_pacer: %s is no IPv4 address\n", options.host.c_str());
    return 2;
  }
  struct sigaction action {};
  action.sa_handler = on_signal;
  ::sigaction(SIGTERM, &action, nullptr);
  ::sigaction(SIGINT, &action, nullptr);

  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(static_cast<double>(rangekit::ls5::udp_record_count) / options.rate_hz));
  const auto start = Clock::now() + std::chrono::milliseconds(10);
  const auto end =
      options.seconds > 0
          ? start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.seconds))
          : Clock::time_point::max();
  // The next packet of each sensor; the sensors take turns in a fixed order, sensor i at i/N of a period.
  std::vector<std::uint32_t> next_packet(static_cast<std::size_t>(options.sensors), 0);
  std::vector<Sent> sent;
  sent.reserve(static_cast<std::size_t>(options.sensors) * 4096);
  std::array<std::uint8_t, rangekit::ls5::udp_packet_size> datagram{};
  std::uint64_t failed = 0;
  for (std::uint64_t slot = 0; !stopping; ++slot) {
    const auto sensor = static_cast<int>(slot % static_cast<std::uint64_t>(options.sensors));
    const std::uint32_t packet = next_packet[static_cast<std::size_t>(sensor)]++;
    const auto due = start + period * packet + period * sensor / options.sensors;
    if (due >= end) break;
    const auto due_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(due.time_since_epoch()).count();
    const timespec wake{static_cast<time_t>(due_ns / 1000000000), static_cast<long>(due_ns % 1000000000)};
    while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &wake, nullptr) == EINTR && !stopping) {
    }
    if (stopping) break;
    fill(datagram, sensor, packet);
    to.sin_port = htons(static_cast<std::uint16_t>(options.first_port + sensor));
    const auto at = Clock::now();
    if (::sendto(sock, datagram.data(), datagram.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to) < 0) {
      ++failed;  // nobody listening yet (ECONNREFUSED on loopback): counted, not fatal
      continue;
    }
    sent.push_back(
        {sensor, packet, std::chrono::duration_cast<std::chrono::nanoseconds>(at.time_since_epoch()).count()});
  }
  ::close(sock);
  if (!options.log.empty()) {
    std::FILE* file = std::fopen(options.log.c_str(), "w");
    if (file == nullptr) {
      std::perror("udp_pacer: log");
      return 1;
    }
    for (const Sent& one : sent)
      std::fprintf(file, "%d %u %lld\n", one.sensor, one.packet, static_cast<long long>(one.at_ns));
    std::fclose(file);
  }
  std::fprintf(stderr, "udp_pacer: %zu packets sent, %llu refused\n", sent.size(),
               static_cast<unsigned long long>(failed));
  return 0;
}
