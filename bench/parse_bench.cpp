// Parser throughput against baselines measured in the same run: memchr over the
// buffer (issue 3 goal: >= 100 MB/s per core, no heap allocation per frame) and a
// plain from_chars parser doing the same work (issue 17 goal: at least as fast).
#include <benchmark/benchmark.h>

#include <array>
#include <cstring>
#include <map>
#include <string>

#include "allocation_counter.hpp"
#include "plain_parsers.hpp"
#include "rangekit/core/framer.hpp"
#include "rangekit/ls5/reply.hpp"
#include "rangekit/ls5/udp_packet.hpp"
#include "rangekit/uls/frame.hpp"
#include "rangekit/uls/measurement.hpp"
#include "streams.hpp"

namespace {

using rangekit::Bytes;
using rangekit::FrameAssembler;
namespace plain = rangekit::bench::plain;

constexpr std::size_t stream_bytes = 4 << 20;  // 4 MiB per pass
constexpr std::size_t read_chunk = 4096;       // what one serial read might return

const std::string& uls_stream() {
  static const std::string stream = rangekit::bench::uls_binning_stream(stream_bytes, 42);
  return stream;
}
const std::string& uls_averaging_stream() {
  static const std::string stream = rangekit::bench::uls_averaging_stream(stream_bytes, 42, false);
  return stream;
}
const std::string& uls_intensity_stream() {
  static const std::string stream = rangekit::bench::uls_averaging_stream(stream_bytes, 42, true);
  return stream;
}
const std::string& ls5_stream() {
  static const std::string stream = rangekit::bench::ls5_stream(stream_bytes, 42);
  return stream;
}
const std::string& udp_stream() {
  static const std::string stream = rangekit::bench::ls5_udp_stream(stream_bytes, 42);
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

// rangekit's ULS path as the driver runs it: the framer over 4 KiB reads, then
// decode_measurement with the unit's settings (U11).
void run_uls_decode(benchmark::State& state, const std::string& stream, rangekit::uls::Mode mode,
                    rangekit::uls::DisplayMode display) {
  const rangekit::uls::MeasurementContext context{mode, display, rangekit::uls::Units::metres, false};
  double checksum = 0;
  auto decode = [&](Bytes frame) {
    auto measurement = rangekit::uls::decode_measurement(frame, context);
    if (!measurement) return false;
    if (const auto* target = std::get_if<rangekit::uls::BinningTarget>(&measurement->reading)) {
      checksum += target->range.metres + target->strength;
    } else if (const auto* averaging = std::get_if<rangekit::uls::AveragingReading>(&measurement->reading)) {
      checksum += averaging->range->metres + averaging->pulse_width_ps.value_or(0);
    }
    return true;
  };
  std::size_t frames = 0;
  (void)parse_stream(stream, &rangekit::uls::scan_frame, decode);  // warm-up: static buffers
  const auto before = rangekit::bench::allocation_count();
  for (auto _ : state) benchmark::DoNotOptimize(frames = parse_stream(stream, &rangekit::uls::scan_frame, decode));
  benchmark::DoNotOptimize(checksum);
  report(state, stream.size(), frames, rangekit::bench::allocation_count() - before);
}

// The plain from_chars parser (bench/plain_parsers.hpp) over the same bytes, same run.
void run_uls_plain(benchmark::State& state, const std::string& stream, plain::UlsShape shape) {
  double checksum = 0;
  std::size_t frames = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(frames = plain::parse_uls_stream(stream, shape, [&](const plain::UlsLine& line) {
                               checksum += line.range_m + line.strength + line.pulse_width_ps;
                             }));
  }
  benchmark::DoNotOptimize(checksum);
  report(state, stream.size(), frames, 0);
}

void uls_binning_decode(benchmark::State& state) {
  run_uls_decode(state, uls_stream(), rangekit::uls::Mode::binning, rangekit::uls::DisplayMode::range);
}
void uls_binning_plain(benchmark::State& state) { run_uls_plain(state, uls_stream(), plain::UlsShape::binning); }
void uls_averaging_decode(benchmark::State& state) {
  run_uls_decode(state, uls_averaging_stream(), rangekit::uls::Mode::averaging, rangekit::uls::DisplayMode::range);
}
void uls_averaging_plain(benchmark::State& state) {
  run_uls_plain(state, uls_averaging_stream(), plain::UlsShape::range);
}
void uls_intensity_decode(benchmark::State& state) {
  run_uls_decode(state, uls_intensity_stream(), rangekit::uls::Mode::averaging,
                 rangekit::uls::DisplayMode::range_and_intensity);
}
void uls_intensity_plain(benchmark::State& state) {
  run_uls_plain(state, uls_intensity_stream(), plain::UlsShape::range_and_intensity);
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

void ls5_stream_plain(benchmark::State& state) {
  std::uint64_t checksum = 0;
  std::size_t frames = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(frames =
                                 plain::parse_ls5_stream(ls5_stream(), [&](std::uint16_t code) { checksum += code; }));
  }
  benchmark::DoNotOptimize(checksum);
  report(state, ls5_stream().size(), frames, 0);
}

// UDP datagrams of section 10: 8192 different ones, one after another.
Bytes udp_datagram(std::size_t index) {
  return {reinterpret_cast<const std::uint8_t*>(udp_stream().data()) + index * rangekit::ls5::udp_packet_size,
          rangekit::ls5::udp_packet_size};
}
std::size_t udp_datagrams() { return udp_stream().size() / rangekit::ls5::udp_packet_size; }

// The floor for a datagram: one plain XOR pass over its bytes, the least a
// receiver that checks the checksum must do, eight bytes at a time.
void ls5_udp_xor_baseline(benchmark::State& state) {
  for (auto _ : state) {
    for (std::size_t i = 0; i < udp_datagrams(); ++i) {
      const Bytes datagram = udp_datagram(i);
      benchmark::DoNotOptimize(datagram.data());
      std::uint64_t folded = 0;
      for (std::size_t at = 0; at < datagram.size(); at += sizeof folded) {
        std::uint64_t word = 0;
        std::memcpy(&word, datagram.data() + at, sizeof word);
        folded ^= word;
      }
      benchmark::DoNotOptimize(folded);
    }
  }
  report(state, udp_stream().size(), udp_datagrams(), 0);
}

// rangekit's checksum (the XOR of bytes 0-509, L12) over the same datagrams.
void ls5_udp_checksum(benchmark::State& state) {
  for (auto _ : state) {
    for (std::size_t i = 0; i < udp_datagrams(); ++i) {
      const Bytes datagram = udp_datagram(i);
      benchmark::DoNotOptimize(datagram.data());
      benchmark::DoNotOptimize(rangekit::ls5::udp_checksum(datagram.first<rangekit::ls5::udp_packet_size>()));
    }
  }
  report(state, udp_stream().size(), udp_datagrams(), 0);
}

void ls5_udp_decode(benchmark::State& state) {
  std::uint64_t checksum = 0;
  std::size_t decoded = 0;
  const auto before = rangekit::bench::allocation_count();
  for (auto _ : state) {
    decoded = 0;
    for (std::size_t i = 0; i < udp_datagrams(); ++i) {
      auto packet = rangekit::ls5::decode_udp_packet(udp_datagram(i));
      if (!packet) continue;
      checksum += packet->records[i % rangekit::ls5::udp_record_count].code + packet->counter;
      ++decoded;
    }
  }
  benchmark::DoNotOptimize(checksum);
  report(state, udp_stream().size(), decoded, rangekit::bench::allocation_count() - before);
}

void ls5_udp_plain(benchmark::State& state) {
  std::uint64_t checksum = 0;
  std::size_t decoded = 0;
  plain::UdpDatagram datagram;
  for (auto _ : state) {
    decoded = 0;
    for (std::size_t i = 0; i < udp_datagrams(); ++i) {
      if (!plain::parse_udp_datagram(udp_datagram(i), datagram)) continue;
      checksum += datagram.records[i % 168].code + datagram.counter;
      ++decoded;
    }
  }
  benchmark::DoNotOptimize(checksum);
  report(state, udp_stream().size(), decoded, 0);
}

BENCHMARK(uls_memchr_baseline)->Unit(benchmark::kMillisecond);
BENCHMARK(uls_binning_decode)->Unit(benchmark::kMillisecond);
BENCHMARK(uls_binning_plain)->Unit(benchmark::kMillisecond);
BENCHMARK(uls_averaging_decode)->Unit(benchmark::kMillisecond);
BENCHMARK(uls_averaging_plain)->Unit(benchmark::kMillisecond);
BENCHMARK(uls_intensity_decode)->Unit(benchmark::kMillisecond);
BENCHMARK(uls_intensity_plain)->Unit(benchmark::kMillisecond);
BENCHMARK(ls5_memchr_baseline)->Unit(benchmark::kMillisecond);
BENCHMARK(ls5_stream_decode)->Unit(benchmark::kMillisecond);
BENCHMARK(ls5_stream_plain)->Unit(benchmark::kMillisecond);
BENCHMARK(ls5_udp_xor_baseline)->Unit(benchmark::kMillisecond);
BENCHMARK(ls5_udp_checksum)->Unit(benchmark::kMillisecond);
BENCHMARK(ls5_udp_decode)->Unit(benchmark::kMillisecond);
BENCHMARK(ls5_udp_plain)->Unit(benchmark::kMillisecond);

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

// Issue 17 item 1: each decoder against the plain from_chars parser of the same
// stream in the same run (goal >= 1.0x), and the UDP checksum against a plain XOR pass (>= 0.5x).
void print_decoder_row(const SummaryReporter& reporter, const char* label, const char* decoder, const char* baseline,
                       double goal) {
  const auto d = reporter.figures.find(decoder);
  const auto b = reporter.figures.find(baseline);
  if (d == reporter.figures.end() || b == reporter.figures.end()) return;
  const double mb = d->second.bytes_per_second / 1e6;
  const double base_mb = b->second.bytes_per_second / 1e6;
  const double ratio = base_mb > 0 ? mb / base_mb : 0.0;
  std::printf("%-24s %9.1f MB/s  %-22s %9.1f MB/s  ratio %5.2fx  goal >= %.1fx: %s\n", label, mb, baseline, base_mb,
              ratio, goal, ratio >= goal ? "met" : "MISSED");
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
  std::printf("\nDecoders against a plain from_chars parser of the same stream, same run (issue 17):\n");
  print_decoder_row(reporter, "ULS averaging", "uls_averaging_decode", "uls_averaging_plain", 1.0);
  print_decoder_row(reporter, "ULS averaging+intensity", "uls_intensity_decode", "uls_intensity_plain", 1.0);
  print_decoder_row(reporter, "ULS binning", "uls_binning_decode", "uls_binning_plain", 1.0);
  print_decoder_row(reporter, "LS5 !ddddd stream", "ls5_stream_decode", "ls5_stream_plain", 1.0);
  print_decoder_row(reporter, "LS5 UDP datagrams", "ls5_udp_decode", "ls5_udp_plain", 1.0);
  print_decoder_row(reporter, "LS5 UDP checksum", "ls5_udp_checksum", "ls5_udp_xor_baseline", 0.5);
  print_host_comparison(reporter, "host LS5 1 kHz @ 921600", "BM_HostLs5Driver1kHz921600/iterations:1/real_time",
                        "BM_CatLs5Floor1kHz921600/iterations:1/real_time");
  print_host_comparison(reporter, "host ULS binning @ 230400", "BM_HostUlsDriverBinning230400/iterations:1/real_time",
                        "BM_CatUlsFloorBinning230400/iterations:1/real_time");
  print_service_comparison(reporter, "BM_ServiceVersusLs5Stream/iterations:1/real_time");
  print_mqtt_comparison(reporter, "BM_MqttServiceVersusPipelines/iterations:1/real_time");
  benchmark::Shutdown();
  return 0;
}
