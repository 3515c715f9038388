// Capture and formatting throughput (issue 6): samples/s written into a SQLite
// capture against a plain fwrite of the same samples as JSON lines (the floor,
// measured in the same run), and how fast samples become jsonl/csv text.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "rangekit/record/capture.hpp"
#include "rangekit/record/format.hpp"

namespace {

using rangekit::Sample;
using rangekit::SampleKind;

constexpr int samples_per_pass = 20000;

// Half ULS averaging, half LS5 results, 1 ms apart: the demo's mix.
const std::vector<Sample>& mixed_samples() {
  static const std::vector<Sample> samples = [] {
    std::vector<Sample> built;
    const auto start = std::chrono::system_clock::now();
    for (int i = 0; i < samples_per_pass; ++i) {
      Sample sample;
      sample.time = start + std::chrono::milliseconds(i);
      if (i % 2 == 0) {
        sample.device = "uls";
        sample.source = "/dev/pts/7";
        sample.address = 3;
        sample.kind = SampleKind::uls_averaging;
        sample.distance_m = 10.0 + i * 0.001;
        sample.pulse_width = 18000;
      } else {
        sample.device = "ls5";
        sample.source = "/dev/pts/9";
        sample.kind = SampleKind::ls5_result;
        sample.code = static_cast<std::uint16_t>(i % 65000);
        sample.distance_mm = i * 0.01;
        sample.signal = rangekit::SignalState::ok;
      }
      built.push_back(sample);
    }
    return built;
  }();
  return samples;
}

std::string bench_file(const char* name) {
  return (std::filesystem::temp_directory_path() / (std::string("rangekit-bench-") + std::to_string(::getpid()) + name))
      .string();
}

void remove_capture(const std::string& path) {
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
}

// The floor: the same samples as JSON lines, formatted beforehand, written with one fwrite.
void record_fwrite_jsonl_baseline(benchmark::State& state) {
  std::string lines;
  for (const auto& sample : mixed_samples()) rangekit::record::append_jsonl(lines, sample);
  const auto path = bench_file(".jsonl");
  for (auto _ : state) {
    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (file == nullptr || std::fwrite(lines.data(), 1, lines.size(), file) != lines.size()) {
      state.SkipWithError("fwrite failed");
    }
    if (file != nullptr) std::fclose(file);
  }
  std::filesystem::remove(path);
  state.SetItemsProcessed(state.iterations() * samples_per_pass);
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(lines.size()));
}

// Every sample through the capture sink: batched WAL transactions, closed at the end of a pass.
void record_capture_write(benchmark::State& state) {
  const auto path = bench_file(".sqlite");
  for (auto _ : state) {
    state.PauseTiming();
    remove_capture(path);
    state.ResumeTiming();
    auto capture = rangekit::record::open_capture(path);
    if (!capture.ok()) {
      state.SkipWithError(capture.error().message.c_str());
      break;
    }
    for (const auto& sample : mixed_samples()) {
      if (!(*capture)->write(sample).ok()) state.SkipWithError("capture write failed");
    }
    capture->reset();  // commits the last batch and closes
  }
  state.SetItemsProcessed(state.iterations() * samples_per_pass);
  state.counters["file_bytes_per_sample"] =
      static_cast<double>(std::filesystem::exists(path) ? std::filesystem::file_size(path) : 0) / samples_per_pass;
  remove_capture(path);
}

void record_format_jsonl(benchmark::State& state) {
  std::string out;
  out.reserve(4 << 20);
  for (auto _ : state) {
    out.clear();
    for (const auto& sample : mixed_samples()) rangekit::record::append_jsonl(out, sample);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * samples_per_pass);
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(out.size()));
}

void record_format_csv(benchmark::State& state) {
  std::string out;
  out.reserve(4 << 20);
  for (auto _ : state) {
    out.clear();
    for (const auto& sample : mixed_samples()) rangekit::record::append_csv(out, sample);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * samples_per_pass);
}

}  // namespace

BENCHMARK(record_fwrite_jsonl_baseline)->Unit(benchmark::kMillisecond);
BENCHMARK(record_capture_write)->Unit(benchmark::kMillisecond);
BENCHMARK(record_format_jsonl)->Unit(benchmark::kMillisecond);
BENCHMARK(record_format_csv)->Unit(benchmark::kMillisecond);
