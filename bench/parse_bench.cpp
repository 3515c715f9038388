// Parser throughput against baselines measured in the same run: memchr over the buffer
// (goal: >= 100 MB/s per core, no heap allocation per frame) and a plain from_chars parser
// doing the same work (goal: at least as fast). Goals: docs/performance.md.
#include <benchmark/benchmark.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <map>
#include <optional>
#include <string>
#include <vector>

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

// rangekit's ULS path as a stream reader runs it: 4 KiB reads into the framer, then
// uls::decode_measurements over what it holds (good averaging lines straight from the
// buffer, every other frame through decode_measurement with the unit's settings, U11).
std::size_t decode_uls_stream(const std::string& stream, const rangekit::uls::MeasurementContext& context,
                              double& checksum) {
  static FrameAssembler assembler(&rangekit::uls::scan_frame, 2 * read_chunk);  // as parse_stream
  assembler.clear();
  std::size_t decoded = 0;
  auto on_measurement = [&](Bytes, const rangekit::uls::Measurement& measurement) {
    if (const auto* target = std::get_if<rangekit::uls::BinningTarget>(&measurement.reading)) {
      checksum += target->range.metres + target->strength;
    } else if (const auto* averaging = std::get_if<rangekit::uls::AveragingReading>(&measurement.reading)) {
      checksum += averaging->range ? averaging->range->metres : 0.0;
      checksum += averaging->pulse_width_ps.value_or(0);
    }
    ++decoded;
  };
  auto on_frame = [&](Bytes frame) {
    auto measurement = rangekit::uls::decode_measurement(frame, context);
    if (measurement) on_measurement(frame, *measurement);
  };
  auto on_rejected = [](const FrameAssembler::Event&) {};
  for (std::size_t offset = 0; offset < stream.size(); offset += read_chunk) {
    const std::size_t size = std::min(read_chunk, stream.size() - offset);
    assembler.push(Bytes(reinterpret_cast<const std::uint8_t*>(stream.data()) + offset, size));
    rangekit::uls::decode_measurements(assembler, context, on_measurement, on_frame, on_rejected);
  }
  return decoded;
}

void run_uls_decode(benchmark::State& state, const std::string& stream, rangekit::uls::Mode mode,
                    rangekit::uls::DisplayMode display) {
  const rangekit::uls::MeasurementContext context{mode, display, rangekit::uls::Units::metres, false};
  double checksum = 0;
  std::size_t frames = 0;
  (void)decode_uls_stream(stream, context, checksum);  // warm-up: static buffers
  const auto before = rangekit::bench::allocation_count();
  for (auto _ : state) benchmark::DoNotOptimize(frames = decode_uls_stream(stream, context, checksum));
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

// rangekit's LS5 path as the stream reader (src/ls5/driver/stream.cpp) runs it: 4 KiB
// reads into the framer, then ls5::decode_replies over what it holds.
std::size_t decode_ls5_stream(const std::string& stream, std::uint64_t& checksum) {
  static FrameAssembler assembler(&rangekit::ls5::scan_reply_frame, 2 * read_chunk);  // as parse_stream
  assembler.clear();
  std::size_t decoded = 0;
  auto on_record = [&](rangekit::ls5::ResultCode code) {
    checksum += code.value;
    ++decoded;
  };
  auto on_reply = [&](Bytes, const rangekit::Result<rangekit::ls5::Reply>& reply) {
    if (!reply) return;
    checksum += reply->result.value;
    ++decoded;
  };
  auto on_rejected = [](const FrameAssembler::Event&) {};
  for (std::size_t offset = 0; offset < stream.size(); offset += read_chunk) {
    const std::size_t size = std::min(read_chunk, stream.size() - offset);
    assembler.push(Bytes(reinterpret_cast<const std::uint8_t*>(stream.data()) + offset, size));
    rangekit::ls5::decode_replies(assembler, on_record, on_reply, on_rejected);
  }
  return decoded;
}

void ls5_stream_decode(benchmark::State& state) {
  std::uint64_t checksum = 0;
  std::size_t frames = 0;
  (void)decode_ls5_stream(ls5_stream(), checksum);
  const auto before = rangekit::bench::allocation_count();
  for (auto _ : state) benchmark::DoNotOptimize(frames = decode_ls5_stream(ls5_stream(), checksum));
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

// The closing table of `make bench`: each figure beside its baseline from
// the same run, the ratio, the goal and whether it was met, as a Markdown table that
// docs/performance.md keeps.
struct GoalRow {
  std::string path;
  std::string figure;
  std::string baseline;
  double ratio = 0;
  std::string goal;
  bool met = false;
  bool counted = true;  // false: a figure beside the goals (where a site breaks), neither met nor missed
};

class GoalTable {
 public:
  explicit GoalTable(const SummaryReporter& reporter) : reporter_(reporter) {}

  // A figure of benchmark `name` (a counter, or bytes_per_second as "MB/s"); nullopt when it did not run.
  std::optional<double> value(const std::string& name, const std::string& counter) const {
    const auto found = reporter_.figures.find(name);
    if (found == reporter_.figures.end()) return std::nullopt;
    if (counter == "MB/s") return found->second.bytes_per_second / 1e6;
    if (counter == "allocs_per_frame") return found->second.allocs_per_frame;
    const auto it = found->second.counters.find(counter);
    if (it == found->second.counters.end()) return std::nullopt;
    return it->second;
  }

  void add(GoalRow row) { rows_.push_back(std::move(row)); }

  void print() const {
    std::printf("\n| path | rangekit | baseline, same run | ratio | goal | |\n|---|---|---|---|---|---|\n");
    for (const GoalRow& row : rows_) {
      std::printf("| %s | %s | %s | %.2f | %s | %s |\n", row.path.c_str(), row.figure.c_str(), row.baseline.c_str(),
                  row.ratio, row.goal.c_str(),
                  !row.counted ? "-"
                  : row.met    ? "met"
                               : "**MISSED**");
    }
    std::size_t met = 0;
    std::size_t counted = 0;
    for (const GoalRow& row : rows_) {
      met += row.counted && row.met ? 1 : 0;
      counted += row.counted ? 1 : 0;
    }
    std::printf("\n%zu of %zu goals met in this run.\n", met, counted);
  }

 private:
  const SummaryReporter& reporter_;
  std::vector<GoalRow> rows_;
};

std::string text_of(const char* format, double a, double b = 0) {
  std::array<char, 128> buffer{};
  std::snprintf(buffer.data(), buffer.size(), format, a, b);
  return buffer.data();
}

// A decoder against memchr (UDP: an XOR pass) over the same buffer; goal >= 100 MB/s a core, no allocation.
void add_memchr_row(GoalTable& table, const char* path, const char* decoder, const char* baseline,
                    const char* baseline_name = "memchr") {
  const auto mb = table.value(decoder, "MB/s");
  const auto base = table.value(baseline, "MB/s");
  const auto allocs = table.value(decoder, "allocs_per_frame");
  if (!mb || !base || !allocs) return;
  table.add({path, text_of("%.0f MB/s, %.4f allocations/frame", *mb, *allocs),
             std::string(baseline_name) + text_of(" %.0f MB/s", *base), *base > 0 ? *mb / *base : 0,
             ">= 100 MB/s, no allocation", *mb >= 100.0 && *allocs < 0.001});
}

// Each decoder against the plain from_chars parser of the same stream
// (goal >= 1.0x), and the UDP checksum against a plain XOR pass (>= 0.5x).
void add_ratio_row(GoalTable& table, const char* path, const char* decoder, const char* baseline,
                   const char* baseline_name, double goal) {
  const auto mb = table.value(decoder, "MB/s");
  const auto base = table.value(baseline, "MB/s");
  if (!mb || !base) return;
  const double ratio = *base > 0 ? *mb / *base : 0;
  table.add({path, text_of("%.0f MB/s", *mb), std::string(baseline_name) + text_of(" %.0f MB/s", *base), ratio,
             text_of(">= %.1fx", goal), ratio >= goal});
}

// Host streaming: the driver against cat of the same pty, in turn, three pairs in one run
// (bench/host_stream_rig.hpp run_paired; the pair with the median CPU ratio is shown).
// Goals: >= 95 % of the records delivered, none lost in any run, < 5 % of a core, and
// CPU <= 1.5x cat's.
void add_host_rows(GoalTable& table, const char* path, const char* name) {
  const auto delivered = table.value(name, "drv_delivered_pct");
  const auto cpu = table.value(name, "drv_host_cpu_pct");
  const auto lost = table.value(name, "lost_all");
  const auto cat_delivered = table.value(name, "cat_delivered_pct");
  const auto cat_cpu = table.value(name, "cat_host_cpu_pct");
  const auto ratio = table.value(name, "cpu_ratio");
  const auto low = table.value(name, "cpu_ratio_low");
  const auto high = table.value(name, "cpu_ratio_high");
  if (!delivered || !cpu || !lost || !cat_delivered || !cat_cpu || !ratio || !low || !high) return;
  table.add({path, text_of("%.2f %% delivered, %.0f lost", *delivered, *lost),
             text_of("cat %.2f %% delivered", *cat_delivered), *cat_delivered > 0 ? *delivered / *cat_delivered : 0,
             ">= 95 %, none lost, < 5 % of a core", *delivered >= 95.0 && *lost == 0 && *cpu < 5.0});
  table.add({std::string(path) + ", CPU (median of 3 pairs)", text_of("%.2f %% of a core", *cpu),
             text_of("cat %.2f %% (", *cat_cpu) + text_of("pair ratios %.2f to ", *low) + text_of("%.2f)", *high),
             *ratio, "<= 1.5x cat", *ratio <= 1.5 && *cat_cpu > 0});
}

// No allocation per record on the live path, counted by the bench's
// replacing operator new over the driver benches' window (records of LS5, bursts of ULS
// binning), the most of the three driver runs. The hand-off vectors grow when a batch is
// larger than any before (a late consumer): a rare allocation that does not come with
// every record, so the goal is met below one allocation per hundred records.
void add_allocation_row(GoalTable& table, const char* path, const char* name, const char* record) {
  const auto most = table.value(name, "allocs_per_record_max");
  const auto in_window = table.value(name, "drv_allocs_in_window");
  const auto records = table.value(name, "drv_records_in_window");
  if (!most || !in_window || !records) return;
  table.add({std::string(path) + ", allocations per " + record + " on the live path",
             text_of("at most %.4f (median pair: %.0f in the window, ", *most, *in_window) +
                 text_of("%.0f ", *records) + record + "s)",
             "-", *most, "0 per " + std::string(record), *most < 0.01 && *records > 0});
}

// The sensor service: CPU against `rangekit ls5 stream` of the same LS5s, same run;
// goals: at most 3x that CPU, RSS <= 64 MB, record-to-SSE latency p99 <= 20 ms.
void add_service_rows(GoalTable& table, const char* name) {
  const auto ratio = table.value(name, "cpu_ratio");
  const auto cpu = table.value(name, "service_cpu_pct");
  const auto base = table.value(name, "baseline_cpu_pct");
  const auto rss = table.value(name, "peak_rss_MB");
  const auto p50 = table.value(name, "lat_p50_ms");
  const auto p99 = table.value(name, "lat_p99_ms");
  const auto samples = table.value(name, "lat_samples");
  if (!ratio || !cpu || !base || !rss || !p50 || !p99 || !samples) return;
  const std::string path = "service: 2 LS5 1 kHz + 4 ULS + 10 SSE clients";
  table.add({path + ", CPU", text_of("%.1f %% of a core", *cpu), text_of("ls5 stream x2 %.1f %%", *base), *ratio,
             "<= 3x", *ratio <= 3.0 && *base > 0});
  table.add({path + ", peak RSS", text_of("%.1f MB", *rss), "-", *rss / 64.0, "<= 64 MB", *rss <= 64.0});
  table.add({path + ", latency pty to SSE", text_of("p99 %.1f ms (p50 %.2f)", *p99, *p50), "-", *p99 / 20.0,
             "p99 <= 20 ms", *p99 <= 20.0 && *samples > 0});
}

// The MQTT bridge: CPU against `ls5 stream | mosquitto_pub -l` of the same
// LS5s, same run; goals: less CPU, record-to-subscriber latency p99 <= 10 ms, no loss.
void add_mqtt_rows(GoalTable& table, const char* name) {
  const auto cpu = table.value(name, "service_cpu_pct");
  const auto base = table.value(name, "baseline_cpu_pct");
  const auto p99 = table.value(name, "lat_p99_ms");
  const auto records = table.value(name, "records");
  const auto lost = table.value(name, "lost");
  if (!cpu || !base || !p99 || !records || !lost) return;
  const std::string path = "mqtt: 2 LS5 1 kHz, every sample";
  table.add({path + ", CPU", text_of("%.1f %% of a core", *cpu),
             text_of("ls5 stream piped to mosquitto_pub, x2: %.1f %%", *base), *base > 0 ? *cpu / *base : 0, "< 1x",
             *cpu<*base&& * base> 0});
  table.add({path + ", latency", text_of("p99 %.1f ms", *p99), "-", *p99 / 10.0, "p99 <= 10 ms",
             *p99 <= 10.0 && *records > 0});
  table.add(
      {path + ", loss", text_of("%.0f of %.0f lost", *lost, *records), "-", 0, "none", *lost == 0 && *records > 0});
}

// The Modbus face: 10 clients at 100 Hz each; goals: response p99 <= 5 ms, none failed, and
// at most 20 us of the service's CPU per request over the same demo without the face, same
// run. A loopback request is a wake-up, a recv and a send: perf puts most of the added CPU in
// the kernel's scheduler, so the goal is per request, not a ratio to an idle demo.
// With 32 clients (the most asked of the face at this rate) the response and none failed are
// the goals; the CPU per request is shown beside them.
void add_modbus_rows(GoalTable& table, const char* name, const std::string& path, bool cpu_goal) {
  const auto cpu = table.value(name, "service_cpu_pct");
  const auto base = table.value(name, "baseline_cpu_pct");
  const auto added = table.value(name, "added_cpu_us_per_request");
  const auto p99 = table.value(name, "resp_p99_ms");
  const auto p50 = table.value(name, "resp_p50_ms");
  const auto requests = table.value(name, "requests");
  const auto failed = table.value(name, "failed");
  if (!cpu || !base || !added || !p99 || !p50 || !requests || !failed) return;
  std::string counts = text_of("%.0f requests, ", *requests) + text_of("%.0f failed", *failed);
  if (!cpu_goal) counts += text_of(", %.1f us CPU per request", *added);
  table.add({path + ", response", text_of("p99 %.2f ms (p50 %.2f)", *p99, *p50), counts, *p99 / 5.0, "p99 <= 5 ms",
             *p99 <= 5.0 && *requests > 0 && *failed == 0});
  if (!cpu_goal) return;
  table.add({path + ", CPU per request", text_of("%.1f us", *added) + text_of(" (%.1f %% of a core)", *cpu),
             text_of("without the face %.1f %%", *base), *added / 20.0, "<= 20 us", *base > 0 && *added <= 20.0});
}

// The tap in a line: a chunk's p99 from one end to the other through it, each way, against
// the same chunk across one pty without it, same run; goal: it adds at most 1 ms.
void add_tap_rows(GoalTable& table, const char* name) {
  const auto direct = table.value(name, "direct_p99_ms");
  const auto direct_p50 = table.value(name, "direct_p50_ms");
  const auto to_host = table.value(name, "to_host_p99_ms");
  const auto to_host_p50 = table.value(name, "to_host_p50_ms");
  const auto to_sensor = table.value(name, "to_sensor_p99_ms");
  const auto cpu = table.value(name, "tap_cpu_pct");
  if (!direct || !direct_p50 || !to_host || !to_host_p50 || !to_sensor || !cpu) return;
  const double added = std::max(*to_host, *to_sensor) - *direct;
  table.add({"tap: a 7-byte chunk at 500 Hz through rangekit tap, each way",
             text_of("p99 %.2f ms to the host", *to_host) + text_of(", %.2f ms to the sensor", *to_sensor) +
                 text_of(" (p50 %.2f; ", *to_host_p50) + text_of("tap %.1f %% of a core)", *cpu),
             text_of("one pty without it: p99 %.2f ms", *direct) + text_of(" (p50 %.2f)", *direct_p50), added,
             "adds <= 1 ms", added <= 1.0});
}

// The tap's throughput one way, against one pty without it, same run; goal: ten times the
// fastest line either document lists (the LS5's 921600 baud, 92 kB/s), so it never limits a line.
void add_tap_throughput_row(GoalTable& table, const char* name) {
  const auto direct = table.value(name, "direct_MBps");
  const auto tapped = table.value(name, "tapped_MBps");
  const auto cpu = table.value(name, "tap_cpu_pct");
  if (!direct || !tapped || !cpu) return;
  constexpr double goal_mbps = 0.92;
  table.add({"tap: 16 MB of ULS replies through rangekit tap, one way",
             text_of("%.1f MB/s", *tapped) + text_of(" (tap %.0f %% of a core)", *cpu),
             text_of("one pty without it: %.1f MB/s", *direct), goal_mbps / *tapped, ">= 0.92 MB/s (10x 921600 baud)",
             *tapped >= goal_mbps});
}

// RS-485 polling (bench/uls_bus_bench.cpp): unit polls (US and BM) a second against the wire's
// minimum for the same bytes and turnarounds, same run; goal: at least 85 % of it.
void add_bus_poll_row(GoalTable& table, int units, int baud) {
  const std::string name =
      "BM_UlsBusPoll/" + std::to_string(units) + "/" + std::to_string(baud) + "/iterations:1/real_time";
  const auto polls = table.value(name.c_str(), "unit_polls_per_s");
  const auto wire = table.value(name.c_str(), "wire_polls_per_s");
  const auto efficiency = table.value(name.c_str(), "efficiency");
  const auto failed = table.value(name.c_str(), "failed");
  if (!polls || !wire || !efficiency || !failed) return;
  table.add({"RS-485 poll: " + std::to_string(units) + " ULS at " + std::to_string(baud) + " baud, US+BM each",
             text_of("%.1f unit polls/s", *polls) + text_of(" (%.0f %% of the wire", 100.0 * *efficiency) +
                 text_of(", %.0f failed)", *failed),
             text_of("wire minimum: %.1f/s", *wire), 0.85 / *efficiency, ">= 85 % of the wire",
             *efficiency >= 0.85 && *failed == 0});
}

// A site on one box (bench/site_scale_bench.cpp, `make bench-scale`): N UDP LS5 at 1 kHz plus
// 8 serial LS5 and 32 bus ULS, every sample captured, 10 SSE clients, MQTT, Modbus. Goals at
// N = 64; each N's row asks for no sample lost; past 64 the rows show where it breaks.
void add_scale_rows(GoalTable& table) {
  const auto name = [](int n, int same) {
    return "BM_SiteScale/" + std::to_string(n) + "/" + std::to_string(same) + "/iterations:1/real_time";
  };
  const auto figure = [&](int n, const char* counter) { return table.value(name(n, 0), counter); };
  for (const int n : {1, 8, 32, 64, 128, 192, 256}) {
    const auto cpu = figure(n, "service_cpu_pct");
    const auto rate = figure(n, "samples_per_s");
    const auto rss = figure(n, "rss_MB");
    const auto p99 = figure(n, "lat_p99_ms");
    const auto lost = figure(n, "udp_lost");
    const auto rows_lost = figure(n, "udp_rows_lost");
    const auto reported = figure(n, "lost_reported");
    const auto rig = figure(n, "pacer_cpu_pct");
    const auto emulators = figure(n, "emulators_cpu_pct");
    if (!cpu || !rate || !rss || !p99 || !lost || !rows_lost || !reported || !rig || !emulators) continue;
    const double all_lost = *lost + *rows_lost + *reported;
    const std::string path = "site: " + std::to_string(n) + " UDP LS5 + 8 serial LS5 + 32 ULS";
    table.add({path + ", CPU, RSS, p99 packet to SSE, lost",
               text_of("%.1f %% of a core, ", *cpu) + text_of("%.0f samples/s, ", *rate) + text_of("%.0f MB, ", *rss) +
                   text_of("p99 %.1f ms, ", *p99) + text_of("%.0f lost", all_lost),
               text_of("rig %.1f %% + emulators ", *rig) + text_of("%.1f %%", *emulators), *cpu / 60.0,
               n == 64  ? "<= 60 %, 0 lost, p99 <= 20 ms, <= 256 MB"
               : n < 64 ? "0 lost"
                        : "none: where it breaks",
               all_lost == 0 && (n != 64 || (*cpu <= 60 && *p99 <= 20 && *rss <= 256)), n <= 64});
  }
  const auto same = table.value(name(64, 1), "service_cpu_pct");
  const auto same_rate = table.value(name(64, 1), "samples_per_s");
  const auto separate = table.value("BM_SiteScaleSeparateProcesses/64/iterations:1/real_time", "cpu_pct");
  if (same && same_rate && separate && *same_rate > 0) {
    const double ratio = (*same / *same_rate) / (*separate / 64000.0);
    table.add({"site: 64 UDP LS5, capture of all, CPU per sample",
               text_of("%.1f %% of a core (", *same) + text_of("%.0f samples/s)", *same_rate),
               text_of("64 `ls5 udp --format jsonl --capture`: %.1f %%", *separate), ratio, "<= 0.5x", ratio <= 0.5});
  }
  const auto cpu8 = figure(8, "service_cpu_pct");
  const auto cpu64 = figure(64, "service_cpu_pct");
  if (cpu8 && cpu64 && *cpu8 > 0) {
    table.add({"site: CPU at 64 UDP LS5 against 8", text_of("%.1f %% against ", *cpu64) + text_of("%.1f %%", *cpu8), "",
               *cpu64 / *cpu8 / 8.5, "<= 8.5x", *cpu64 / *cpu8 <= 8.5});
  }
  const auto rss8 = figure(8, "rss_MB");
  const auto rss64 = figure(64, "rss_MB");
  if (rss8 && rss64) {
    const double per_sensor = (*rss64 - *rss8) / 56.0;
    table.add({"site: memory per added UDP LS5 (8 to 64)", text_of("%.2f MB", per_sensor),
               text_of("RSS %.0f MB at 8, ", *rss8) + text_of("%.0f at 64", *rss64), per_sensor, "<= 1 MB",
               per_sensor <= 1.0});
  }
  if (const auto per_client = figure(64, "rss_per_client_MB")) {
    table.add({"site: memory per SSE client (64 UDP LS5)", text_of("%.2f MB", *per_client), "11 clients", *per_client,
               "<= 1 MB", *per_client <= 1.0});
  }
}

// The service's bus session (bench/uls_bus_service_bench.cpp): unit polls a second of
// `rangekit serve` against the wire's minimum (goal: 85 %), with `uls bus poll` of the same
// bus beside it; then how long two clients' commands waited beyond their time alone on the
// polled bus, against the poll cycle (goal: one cycle at most).
void add_bus_service_rows(GoalTable& table, int units, int baud) {
  const std::string name =
      "BM_UlsBusService/" + std::to_string(units) + "/" + std::to_string(baud) + "/iterations:1/real_time";
  const auto value = [&](const char* counter) { return table.value(name, counter); };
  const auto polls = value("unit_polls_per_s");
  const auto wire = value("wire_polls_per_s");
  const auto efficiency = value("efficiency");
  const auto library = value("library_polls_per_s");
  const auto failed = value("failed");
  const auto cycle = value("cycle_ms");
  const auto wait = value("wait_p99_ms");
  const auto p50 = value("cmd_p50_ms");
  const auto p99 = value("cmd_p99_ms");
  const auto max = value("cmd_max_ms");
  const auto read = value("alone_read_p50_ms");
  const auto single = value("alone_single_p50_ms");
  const auto commands = value("commands");
  if (!polls || !wire || !efficiency || !library || !failed || !cycle || !wait || !p50 || !p99 || !max || !read ||
      !single || !commands)
    return;
  const std::string path = "RS-485 service: " + std::to_string(units) + " ULS at " + std::to_string(baud) + " baud";
  table.add({path + ", poll",
             text_of("%.1f unit polls/s", *polls) + text_of(" (%.0f %% of the wire)", 100 * *efficiency),
             text_of("wire minimum: %.1f/s", *wire) + text_of(" (uls bus poll: %.1f/s)", *library), 0.85 / *efficiency,
             ">= 85 % of the wire", *efficiency >= 0.85});
  table.add({path + ", 2 clients' read and single",
             text_of("waited p99 %.0f ms", *wait) + text_of(" (response p50 %.0f", *p50) + text_of(", p99 %.0f", *p99) +
                 text_of(", max %.0f ms", *max) + text_of("; %.0f commands", *commands) +
                 text_of(", %.0f failed)", *failed),
             text_of("poll cycle %.0f ms", *cycle) + text_of(" (alone: read %.0f ms", *read) +
                 text_of(", single %.0f ms)", *single),
             *wait / *cycle, "waited <= 1 poll cycle", *wait <= *cycle && *failed == 0});
}

// Emulator pacing (L78): against a minimal absolute-deadline writer, and its CPU against the
// baseline loop of bench/filed_emulator_loop.hpp (no more), same run; the present loop
// rounded to whole milliseconds is shown beside it (bench/emulator_pacing_bench.cpp).
void add_pacing_rows(GoalTable& table, const char* name) {
  const auto p99 = table.value(name, "emu_p99_us");
  const auto writer_p99 = table.value(name, "writer_p99_us");
  const auto together = table.value(name, "emu_together_pct");
  const auto writer_together = table.value(name, "writer_together_pct");
  const auto cpu = table.value(name, "present_cpu_ms_per_s");
  const auto beside_rounded_cpu = table.value(name, "emu_cpu_ms_per_s");
  const auto rounded_cpu = table.value(name, "ms_emu_cpu_ms_per_s");
  const auto filed_cpu = table.value(name, "filed_cpu_ms_per_s");
  const auto low = table.value(name, "p99_ratio_low");
  const auto high = table.value(name, "p99_ratio_high");
  if (!p99 || !writer_p99 || !together || !writer_together || !cpu || !rounded_cpu || !filed_cpu ||
      !beside_rounded_cpu || !low || !high)
    return;
  const std::string path = "LS5 emulator at 1 kHz";
  const double p99_ratio = *writer_p99 > 0 ? *p99 / *writer_p99 : 0;
  table.add(
      {path + ", p99 of abs(interval - period) (median of 3)", text_of("%.0f us", *p99),
       text_of("minimal writer %.0f us (", *writer_p99) + text_of("ratios %.2f to ", *low) + text_of("%.2f)", *high),
       p99_ratio, "<= 1.5x", p99_ratio <= 1.5 && *writer_p99 > 0});
  table.add({path + ", records together with the previous", text_of("%.2f %%", *together),
             text_of("minimal writer %.2f %%", *writer_together),
             *writer_together > 0 ? *together / *writer_together : 0, "<= 1 %", *together <= 1.0});
  table.add({path + ", CPU", text_of("%.1f ms/s", *cpu),
             text_of("loop as filed %.1f ms/s (beside it, rounded to ms: ", *filed_cpu) +
                 text_of("%.1f ms/s against ", *rounded_cpu) + text_of("%.1f)", *beside_rounded_cpu),
             *filed_cpu > 0 ? *cpu / *filed_cpu : 0, "<= 1x", *cpu <= *filed_cpu && *filed_cpu > 0});
}

// The postgres sink (bench/postgres_sink_bench.cpp): the drain of a 60 s backlog against psql
// \copy of as many of the same rows, same run and cluster (>= 0.8x); the service's CPU with
// the sink against without it (<= 2x); the drain after the 60 s outage within 30 s.
void add_postgres_rows(GoalTable& table, const char* name) {
  const auto drain = table.value(name, "drain_rows_per_s");
  const auto copy = table.value(name, "copy_rows_per_s");
  const auto rows = table.value(name, "drain_rows");
  const auto ratio = table.value(name, "cpu_ratio");
  const auto sink_cpu = table.value(name, "sink_cpu_pct");
  const auto plain_cpu = table.value(name, "plain_cpu_pct");
  const auto drain_s = table.value(name, "drain_s");
  const auto backlog = table.value(name, "backlog_rows");
  const auto low = table.value(name, "cpu_ratio_low");
  const auto high = table.value(name, "cpu_ratio_high");
  if (!drain || !copy || !rows || !ratio || !sink_cpu || !plain_cpu || !drain_s || !backlog || !low || !high) return;
  const std::string path = "postgres sink: 2 LS5 1 kHz, every sample";
  table.add({path + ", drain of a 60 s backlog", text_of("%.0f rows/s", *drain),
             text_of("psql \\copy %.0f rows/s (", *copy) + text_of("%.0f rows)", *rows), *copy > 0 ? *drain / *copy : 0,
             ">= 0.8x", *copy > 0 && *drain >= 0.8 * *copy});
  table.add({path + ", service CPU (median of 3 pairs)", text_of("%.1f %% of a core", *sink_cpu),
             text_of("without the sink %.1f %% (", *plain_cpu) + text_of("pair ratios %.2f to ", *low) +
                 text_of("%.2f)", *high),
             *ratio, "<= 2x", *plain_cpu > 0 && *ratio <= 2.0});
  table.add({path + ", drain after a 60 s outage", text_of("%.1f s", *drain_s), text_of("%.0f rows waited", *backlog),
             *drain_s / 30.0, "<= 30 s", *backlog > 0 && *drain_s <= 30.0});
}

// Capture of ULS binning bursts: against raw sqlite3 C, same schema and batching.
void add_capture_row(GoalTable& table, const char* name) {
  const auto ours = table.value(name, "capture_samples_per_s");
  const auto raw = table.value(name, "raw_sqlite_samples_per_s");
  const auto ratio = table.value(name, "ratio");
  if (!ours || !raw || !ratio) return;
  table.add({"capture of ULS binning, 15 targets", text_of("%.0f samples/s", *ours),
             text_of("raw sqlite3 C %.0f samples/s", *raw), *ratio, ">= 0.9x", *ratio >= 0.9});
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  GoalTable table(reporter);
  add_memchr_row(table, "ULS binning decode", "uls_binning_decode", "uls_memchr_baseline");
  add_memchr_row(table, "LS5 stream decode", "ls5_stream_decode", "ls5_memchr_baseline");
  add_memchr_row(table, "LS5 UDP decode", "ls5_udp_decode", "ls5_udp_xor_baseline", "8-byte XOR");
  add_ratio_row(table, "ULS averaging decode", "uls_averaging_decode", "uls_averaging_plain", "plain parser", 1.0);
  add_ratio_row(table, "ULS averaging+intensity decode", "uls_intensity_decode", "uls_intensity_plain", "plain parser",
                1.0);
  add_ratio_row(table, "ULS binning decode", "uls_binning_decode", "uls_binning_plain", "plain parser", 1.0);
  add_ratio_row(table, "LS5 !ddddd decode", "ls5_stream_decode", "ls5_stream_plain", "plain parser", 1.0);
  add_ratio_row(table, "LS5 UDP datagram decode", "ls5_udp_decode", "ls5_udp_plain", "plain parser", 1.0);
  add_ratio_row(table, "LS5 UDP checksum", "ls5_udp_checksum", "ls5_udp_xor_baseline", "8-byte XOR", 0.5);
  const char* ls5_pairs = "BM_Ls5StreamAndCat1kHz921600/iterations:1/real_time";
  const char* uls_pairs = "BM_UlsStreamAndCatBinning230400/iterations:1/real_time";
  add_host_rows(table, "ls5 stream, 1 kHz at 921600", ls5_pairs);
  add_host_rows(table, "uls stream, binning at 230400", uls_pairs);
  add_allocation_row(table, "ls5 stream, 1 kHz at 921600", ls5_pairs, "record");
  add_allocation_row(table, "uls stream, binning at 230400", uls_pairs, "burst");
  add_pacing_rows(table, "BM_EmulatorPacingLs5At1kHz/iterations:1/real_time");
  add_capture_row(table, "record_capture_binning_vs_raw_sqlite/iterations:1/real_time");
  add_service_rows(table, "BM_ServiceVersusLs5Stream/iterations:1/real_time");
  add_mqtt_rows(table, "BM_MqttServiceVersusPipelines/iterations:1/real_time");
  add_modbus_rows(table, "BM_ModbusClientsAt100Hz/10/iterations:1/real_time",
                  "modbus: serve --demo, 10 clients at 100 Hz", true);
  add_modbus_rows(table, "BM_ModbusClientsAt100Hz/32/iterations:1/real_time",
                  "modbus: serve --demo, 32 clients at 100 Hz", false);
  add_tap_rows(table, "BM_TapAddedLatency/iterations:1/real_time");
  add_tap_throughput_row(table, "BM_TapThroughput/iterations:1/real_time");
  for (const int baud : {9600, 115200}) {
    for (const int units : {16, 32}) add_bus_poll_row(table, units, baud);
  }
  for (const int baud : {9600, 115200}) {
    for (const int units : {16, 32}) add_bus_service_rows(table, units, baud);
  }
  add_postgres_rows(table, "BM_PostgresSinkTwoLs5At1kHz/iterations:1/real_time");
  add_scale_rows(table);
  table.print();
  benchmark::Shutdown();
  return 0;
}
