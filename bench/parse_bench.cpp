// Parser throughput against a memchr-over-the-buffer baseline measured in the
// same run (issue 3 goal: >= 100 MB/s per core, no heap allocation per frame).
#include <benchmark/benchmark.h>

#include <array>
#include <cstring>
#include <map>
#include <string>

#include "allocation_counter.hpp"
#include "rangekit/core/framer.hpp"
#include "rangekit/ls5/reply.hpp"
#include "rangekit/ls5/udp_packet.hpp"
#include "rangekit/uls/frame.hpp"
#include "rangekit/uls/measurement.hpp"
#include "streams.hpp"

namespace {

using rangekit::Bytes;
using rangekit::FrameAssembler;

constexpr std::size_t stream_bytes = 4 << 20;  // 4 MiB per pass
constexpr std::size_t read_chunk = 4096;       // what one serial read might return

const std::string& uls_stream() {
  static const std::string stream = rangekit::bench::uls_binning_stream(stream_bytes, 42);
  return stream;
}
const std::string& ls5_stream() {
  static const std::string stream = rangekit::bench::ls5_stream(stream_bytes, 42);
  return stream;
}

// The floor: find every CR with memchr, touching each byte once.
std::size_t count_lines_memchr(const std::string& stream) {
  std::size_t lines = 0;
  const char* at = stream.data();
  const char* end = at + stream.size();
  while ((at = static_cast<const char*>(std::memchr(at, '\r', static_cast<std::size_t>(end - at)))) != nullptr) {
    ++lines;
    ++at;
  }
  return lines;
}

template <class Decode>
std::size_t parse_stream(const std::string& stream, rangekit::ScanFunction scan, Decode&& decode) {
  static FrameAssembler assembler(scan, 2 * read_chunk);
  assembler.clear();
  std::size_t decoded = 0;
  FrameAssembler::Event event;
  for (std::size_t offset = 0; offset < stream.size(); offset += read_chunk) {
    const std::size_t size = std::min(read_chunk, stream.size() - offset);
    assembler.push(Bytes(reinterpret_cast<const std::uint8_t*>(stream.data()) + offset, size));
    while (assembler.next(event)) {
      if (event.kind == FrameAssembler::Event::Kind::frame && decode(event.frame)) ++decoded;
    }
  }
  return decoded;
}

void report(benchmark::State& state, std::size_t bytes, std::size_t frames, std::uint64_t allocations) {
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes));
  state.counters["frames"] = benchmark::Counter(static_cast<double>(frames));
  state.counters["allocs_per_frame"] = benchmark::Counter(
      frames == 0 ? 0.0 : static_cast<double>(allocations) / static_cast<double>(frames * state.iterations()));
}

void uls_memchr_baseline(benchmark::State& state) {
  std::size_t lines = 0;
  const auto before = rangekit::bench::allocation_count();
  for (auto _ : state) benchmark::DoNotOptimize(lines = count_lines_memchr(uls_stream()));
  report(state, uls_stream().size(), lines, rangekit::bench::allocation_count() - before);
}

void uls_binning_decode(benchmark::State& state) {
  const rangekit::uls::MeasurementContext context{rangekit::uls::Mode::binning, rangekit::uls::DisplayMode::range,
                                                  rangekit::uls::Units::metres, false};
  double checksum = 0;
  auto decode = [&](Bytes frame) {
    auto measurement = rangekit::uls::decode_measurement(frame, context);
    if (!measurement) return false;
    if (const auto* target = std::get_if<rangekit::uls::BinningTarget>(&measurement->reading))
      checksum += target->range.metres;
    return true;
  };
  std::size_t frames = 0;
  (void)parse_stream(uls_stream(), &rangekit::uls::scan_frame, decode);  // warm-up: static buffers
  const auto before = rangekit::bench::allocation_count();
  for (auto _ : state)
    benchmark::DoNotOptimize(frames = parse_stream(uls_stream(), &rangekit::uls::scan_frame, decode));
  benchmark::DoNotOptimize(checksum);
  report(state, uls_stream().size(), frames, rangekit::bench::allocation_count() - before);
}

void ls5_memchr_baseline(benchmark::State& state) {
  std::size_t lines = 0;
  const auto before = rangekit::bench::allocation_count();
  for (auto _ : state) benchmark::DoNotOptimize(lines = count_lines_memchr(ls5_stream()));
  report(state, ls5_stream().size(), lines, rangekit::bench::allocation_count() - before);
}

void ls5_stream_decode(benchmark::State& state) {
  std::uint64_t checksum = 0;
  auto decode = [&](Bytes frame) {
    auto reply = rangekit::ls5::parse_reply(frame);
    if (!reply) return false;
    checksum += reply->result.value;
    return true;
  };
  std::size_t frames = 0;
  (void)parse_stream(ls5_stream(), &rangekit::ls5::scan_reply_frame, decode);
  const auto before = rangekit::bench::allocation_count();
  for (auto _ : state)
    benchmark::DoNotOptimize(frames = parse_stream(ls5_stream(), &rangekit::ls5::scan_reply_frame, decode));
  benchmark::DoNotOptimize(checksum);
  report(state, ls5_stream().size(), frames, rangekit::bench::allocation_count() - before);
}

// UDP packets of section 10: decode with checksum and state checks, against a
// plain memchr pass over the same 512 bytes.
std::array<std::uint8_t, rangekit::ls5::udp_packet_size> sample_packet() {
  rangekit::ls5::UdpPacket packet;
  for (std::size_t i = 0; i < packet.records.size(); ++i) {
    packet.records[i] = rangekit::ls5::UdpRecord{static_cast<std::uint16_t>(i * 97 % 0x4000), 0x07};
  }
  packet.serial_number = 157;
  packet.lower_boundary_mm = 8;
  packet.range_mm = 40;
  std::array<std::uint8_t, rangekit::ls5::udp_packet_size> bytes{};
  (void)rangekit::ls5::encode_udp_packet(packet, bytes);
  return bytes;
}

// The floor for a packet: one XOR pass over its bytes, the least a receiver
// that checks the checksum must do.
void ls5_udp_xor_baseline(benchmark::State& state) {
  const auto packet = sample_packet();
  for (auto _ : state) {
    benchmark::DoNotOptimize(packet.data());
    std::uint8_t folded = 0;
    for (const std::uint8_t byte : packet) folded ^= byte;
    benchmark::DoNotOptimize(folded);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * packet.size()));
}

void ls5_udp_decode(benchmark::State& state) {
  const auto packet = sample_packet();
  const auto before = rangekit::bench::allocation_count();
  for (auto _ : state) {
    auto decoded = rangekit::ls5::decode_udp_packet(packet);
    benchmark::DoNotOptimize(decoded);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * packet.size()));
  state.counters["allocs_per_frame"] = benchmark::Counter(
      static_cast<double>(rangekit::bench::allocation_count() - before) / static_cast<double>(state.iterations()));
}

BENCHMARK(uls_memchr_baseline)->Unit(benchmark::kMillisecond);
BENCHMARK(uls_binning_decode)->Unit(benchmark::kMillisecond);
BENCHMARK(ls5_memchr_baseline)->Unit(benchmark::kMillisecond);
BENCHMARK(ls5_stream_decode)->Unit(benchmark::kMillisecond);
BENCHMARK(ls5_udp_xor_baseline);
BENCHMARK(ls5_udp_decode);

// Keeps every run's throughput and allocation counter for the summary.
class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  struct Figures {
    double bytes_per_second = 0;
    double allocs_per_frame = 0;
    std::map<std::string, double> counters;  // every counter, for the host streaming lines
  };
  std::map<std::string, Figures> figures;

  void ReportRuns(const std::vector<Run>& runs) override {
    for (const auto& run : runs) {
      Figures entry;
      if (auto it = run.counters.find("bytes_per_second"); it != run.counters.end())
        entry.bytes_per_second = it->second;
      if (auto it = run.counters.find("allocs_per_frame"); it != run.counters.end())
        entry.allocs_per_frame = it->second;
      for (const auto& [name, counter] : run.counters) entry.counters[name] = counter.value;
      figures[run.benchmark_name()] = entry;
    }
    ConsoleReporter::ReportRuns(runs);
  }
};

void print_comparison(const SummaryReporter& reporter, const char* parser, const char* baseline) {
  const auto p = reporter.figures.find(parser);
  const auto b = reporter.figures.find(baseline);
  if (p == reporter.figures.end() || b == reporter.figures.end()) return;
  const double mb = p->second.bytes_per_second / 1e6;
  const double base_mb = b->second.bytes_per_second / 1e6;
  std::printf(
      "%-22s %9.1f MB/s  = %5.1f%% of %-22s (%9.1f MB/s)  goal >= 100 MB/s: %-7s allocations/frame: %.4f (%s)\n",
      parser, mb, 100.0 * mb / base_mb, baseline, base_mb, mb >= 100.0 ? "met" : "MISSED", p->second.allocs_per_frame,
      p->second.allocs_per_frame < 0.001 ? "none on the hot path" : "ALLOCATES");
}

// Host streaming (issue 6): the driver against cat of the same pty, same run.
// Goal: >= 95 % of the records the sensor put on the wire, none lost, < 5 % of a core.
void print_host_comparison(const SummaryReporter& reporter, const char* label, const char* driver, const char* floor) {
  const auto d = reporter.figures.find(driver);
  const auto f = reporter.figures.find(floor);
  if (d == reporter.figures.end() || f == reporter.figures.end()) return;
  auto value = [](const SummaryReporter::Figures& figures, const char* name) {
    const auto it = figures.counters.find(name);
    return it == figures.counters.end() ? 0.0 : it->second;
  };
  const double delivered = value(d->second, "delivered_pct");
  const double cpu = value(d->second, "host_cpu_pct");
  const double lost = value(d->second, "lost");
  const bool met = delivered >= 95.0 && lost == 0 && cpu < 5.0;
  std::printf("%-26s driver %6.2f%% delivered, lost %.0f, CPU %4.2f%%  | cat floor %6.2f%%, CPU %4.2f%%  goal: %s\n",
              label, delivered, lost, cpu, value(f->second, "delivered_pct"), value(f->second, "host_cpu_pct"),
              met ? "met" : "MISSED");
}

// The sensor service (issue 13): CPU against `rangekit ls5 stream` of the same LS5s, same run;
// goals: at most 3x that CPU, RSS <= 64 MB, record-to-SSE latency p99 <= 20 ms.
void print_service_comparison(const SummaryReporter& reporter, const char* name) {
  const auto s = reporter.figures.find(name);
  if (s == reporter.figures.end()) return;
  auto value = [&](const char* counter) {
    const auto it = s->second.counters.find(counter);
    return it == s->second.counters.end() ? 0.0 : it->second;
  };
  const double ratio = value("cpu_ratio");
  const double rss = value("peak_rss_MB");
  const double p99 = value("lat_p99_ms");
  std::printf(
      "%-26s CPU %5.1f%% (no clients %4.1f%%) vs ls5 stream x2 %4.1f%% = %4.1fx (goal <= 3x: %s); "
      "peak RSS %5.1f MB (goal <= 64: %s); latency p50 %.2f ms p99 %.2f ms (goal <= 20: %s)\n",
      "service 2 LS5 + 4 ULS, 10 SSE", value("service_cpu_pct"), value("no_client_cpu_pct"), value("baseline_cpu_pct"),
      ratio, ratio <= 3.0 ? "met" : "MISSED", rss, rss <= 64.0 ? "met" : "MISSED", value("lat_p50_ms"), p99,
      p99 <= 20.0 && value("lat_samples") > 0 ? "met" : "MISSED");
}

// The MQTT bridge (issue 15): CPU against `ls5 stream | mosquitto_pub -l` of the same
// LS5s, same run; goals: less CPU, record-to-subscriber latency p99 <= 10 ms, no loss.
void print_mqtt_comparison(const SummaryReporter& reporter, const char* name) {
  const auto s = reporter.figures.find(name);
  if (s == reporter.figures.end()) return;
  auto value = [&](const char* counter) {
    const auto it = s->second.counters.find(counter);
    return it == s->second.counters.end() ? 0.0 : it->second;
  };
  const double service = value("service_cpu_pct");
  const double baseline = value("baseline_cpu_pct");
  const double p99 = value("lat_p99_ms");
  const double records = value("records");
  const double lost = value("lost");
  std::printf(
      "%-26s CPU %5.1f%% vs (ls5 stream | mosquitto_pub) x2 %5.1f%% (goal less: %s); latency p50 %.2f ms p99 %.2f "
      "ms max %.2f ms (goal p99 <= 10: %s); lost %.0f of %.0f (goal none: %s)\n",
      "mqtt 2 LS5 1 kHz full rate", service, baseline, service < baseline && baseline > 0 ? "met" : "MISSED",
      value("lat_p50_ms"), p99, value("lat_max_ms"), p99 <= 10.0 && records > 0 ? "met" : "MISSED", lost, records,
      lost == 0 && records > 0 ? "met" : "MISSED");
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  std::printf("\nComparison with the baseline measured in this run (one core):\n");
  print_comparison(reporter, "uls_binning_decode", "uls_memchr_baseline");
  print_comparison(reporter, "ls5_stream_decode", "ls5_memchr_baseline");
  print_comparison(reporter, "ls5_udp_decode", "ls5_udp_xor_baseline");
  print_host_comparison(reporter, "host LS5 1 kHz @ 921600", "BM_HostLs5Driver1kHz921600/iterations:1/real_time",
                        "BM_CatLs5Floor1kHz921600/iterations:1/real_time");
  print_host_comparison(reporter, "host ULS binning @ 230400", "BM_HostUlsDriverBinning230400/iterations:1/real_time",
                        "BM_CatUlsFloorBinning230400/iterations:1/real_time");
  print_service_comparison(reporter, "BM_ServiceVersusLs5Stream/iterations:1/real_time");
  print_mqtt_comparison(reporter, "BM_MqttServiceVersusPipelines/iterations:1/real_time");
  benchmark::Shutdown();
  return 0;
}
