// Capture and formatting throughput: samples/s into a SQLite capture against a plain fwrite
// of the same JSON lines, ULS binning bursts against raw sqlite3 C with the same schema and
// batching, and how fast samples become jsonl/csv text.
#include <benchmark/benchmark.h>
#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "rangekit/ls5/family.hpp"
#include "rangekit/record/capture.hpp"
#include "rangekit/record/format.hpp"
#include "rangekit/uls/family.hpp"

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
        sample.kind = rangekit::uls::kind::averaging;
        sample.set(rangekit::uls::channel::distance_m, 10.0 + i * 0.001);
        sample.set(rangekit::uls::channel::pulse_width_ps, 18000);
      } else {
        sample.device = "ls5";
        sample.source = "/dev/pts/9";
        sample.kind = rangekit::ls5::kind::result;
        sample.set(rangekit::ls5::channel::code, static_cast<std::uint16_t>(i % 65000));
        sample.set(rangekit::ls5::channel::distance_mm, i * 0.01);
        sample.set(rangekit::ls5::channel::signal, rangekit::ls5::SignalState::ok);
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

// ---- Binning bursts against raw sqlite3 ----

constexpr int binning_samples = 20000;
constexpr std::size_t targets_per_sample = 15;

const std::vector<Sample>& binning_samples_list() {
  static const std::vector<Sample> samples = [] {
    std::vector<Sample> built;
    const auto start = std::chrono::system_clock::now();
    for (int i = 0; i < binning_samples; ++i) {
      Sample sample;
      sample.time = start + std::chrono::microseconds(i * 480);
      sample.device = "uls";
      sample.source = "/dev/pts/7";
      sample.address = 3;
      sample.kind = rangekit::uls::kind::binning;
      for (std::size_t t = 0; t < targets_per_sample; ++t) {
        sample.targets.push_back(
            rangekit::TargetHit{1.25 + static_cast<double>(t) * 3.7 + i * 0.001, static_cast<std::uint32_t>(40 + t)});
      }
      built.push_back(sample);
    }
    return built;
  }();
  return samples;
}

// The schema of docs/capture.md's samples table, as src/record/capture.cpp creates it.
constexpr const char* raw_schema_sql =
    "CREATE TABLE samples(seq INTEGER PRIMARY KEY, session INTEGER NOT NULL, time_ns INTEGER NOT NULL, "
    "device TEXT NOT NULL, source TEXT NOT NULL, address INTEGER, kind TEXT NOT NULL, distance_m REAL, "
    "pulse_width INTEGER, targets TEXT, presence INTEGER, pulses_between_events INTEGER, device_error INTEGER, "
    "code INTEGER, distance_mm REAL, signal TEXT, derivative_mm REAL, resolution_mm REAL, suspect INTEGER, "
    "suspect_reason TEXT)";
constexpr const char* raw_insert_sql =
    "INSERT INTO samples(seq, session, time_ns, device, source, address, kind, distance_m, pulse_width, targets, "
    "presence, pulses_between_events, device_error, code, distance_mm, signal, derivative_mm, resolution_mm, suspect, "
    "suspect_reason) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, ?18, ?19, "
    "?20)";

// The floor: what a C programmer writes. One prepared statement, WAL + synchronous=NORMAL,
// a transaction every 1000 samples (CaptureOptions' default), the targets as JSON text
// printed with std::to_chars (shortest round-trip), NULLs for the columns binning lacks.
bool raw_sqlite_binning_pass(const std::string& path) {
  sqlite3* db = nullptr;
  if (sqlite3_open(path.c_str(), &db) != SQLITE_OK) return false;
  bool ok = sqlite3_exec(db, "PRAGMA journal_mode=WAL", nullptr, nullptr, nullptr) == SQLITE_OK &&
            sqlite3_exec(db, "PRAGMA synchronous=NORMAL", nullptr, nullptr, nullptr) == SQLITE_OK &&
            sqlite3_exec(db, raw_schema_sql, nullptr, nullptr, nullptr) == SQLITE_OK;
  sqlite3_stmt* insert = nullptr;
  ok = ok && sqlite3_prepare_v2(db, raw_insert_sql, -1, &insert, nullptr) == SQLITE_OK;
  char targets[2048];
  std::int64_t seq = 1;
  int in_batch = 0;
  for (const auto& sample : binning_samples_list()) {
    if (!ok) break;
    if (in_batch == 0) ok = sqlite3_exec(db, "BEGIN", nullptr, nullptr, nullptr) == SQLITE_OK;
    // The shortest round-trip text (std::to_chars), the cheapest exact way there is.
    char* out = targets;
    char* const end = targets + sizeof targets;
    *out++ = '[';
    for (std::size_t t = 0; t < sample.targets.size(); ++t) {
      static constexpr std::string_view first = "{\"distance_m\":";
      static constexpr std::string_view next = ",{\"distance_m\":";
      static constexpr std::string_view strength = ",\"strength\":";
      const std::string_view open = t == 0 ? first : next;
      out = std::copy(open.begin(), open.end(), out);
      out = std::to_chars(out, end, sample.targets[t].distance_m).ptr;
      out = std::copy(strength.begin(), strength.end(), out);
      out = std::to_chars(out, end, sample.targets[t].strength).ptr;
      *out++ = '}';
    }
    *out++ = ']';
    const auto used = static_cast<std::size_t>(out - targets);
    sqlite3_bind_int64(insert, 1, seq++);
    sqlite3_bind_int64(insert, 2, 1);
    sqlite3_bind_int64(insert, 3,
                       std::chrono::duration_cast<std::chrono::nanoseconds>(sample.time.time_since_epoch()).count());
    sqlite3_bind_text(insert, 4, sample.device.data(), static_cast<int>(sample.device.size()), SQLITE_STATIC);
    sqlite3_bind_text(insert, 5, sample.source.data(), static_cast<int>(sample.source.size()), SQLITE_STATIC);
    sqlite3_bind_int64(insert, 6, sample.address);
    sqlite3_bind_text(insert, 7, "uls_binning", -1, SQLITE_STATIC);
    sqlite3_bind_null(insert, 8);
    sqlite3_bind_null(insert, 9);
    sqlite3_bind_text(insert, 10, targets, static_cast<int>(used), SQLITE_STATIC);
    for (int column = 11; column <= 18; ++column) sqlite3_bind_null(insert, column);
    sqlite3_bind_int64(insert, 19, 0);
    sqlite3_bind_null(insert, 20);
    ok = sqlite3_step(insert) == SQLITE_DONE && ok;
    sqlite3_reset(insert);
    if (++in_batch == 1000) {
      ok = ok && sqlite3_exec(db, "COMMIT", nullptr, nullptr, nullptr) == SQLITE_OK;
      in_batch = 0;
    }
  }
  if (ok && in_batch > 0) ok = sqlite3_exec(db, "COMMIT", nullptr, nullptr, nullptr) == SQLITE_OK;
  sqlite3_finalize(insert);
  sqlite3_close(db);
  return ok;
}

bool capture_binning_pass(const std::string& path) {
  auto capture = rangekit::record::open_capture(path);
  if (!capture.ok()) return false;
  for (const auto& sample : binning_samples_list()) {
    if (!(*capture)->write(sample).ok()) return false;
  }
  capture->reset();  // commits the last batch and closes
  return true;
}

double thread_cpu_seconds() {
  timespec spent{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &spent);
  return static_cast<double>(spent.tv_sec) + static_cast<double>(spent.tv_nsec) / 1e9;
}

struct PassTime {
  double wall_s = 0;
  double cpu_s = 0;
};

template <class Pass>
PassTime timed_pass(const std::string& path, Pass pass, bool& ok) {
  remove_capture(path);
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = thread_cpu_seconds();
  ok = pass(path) && ok;
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
          thread_cpu_seconds() - cpu_start};
}

// Both writers in turn, five passes each, interleaved so that they share the machine's
// load; the medians are compared, of wall time (the figure) and of CPU time (the writes
// themselves, without the waits for the disk that a loaded machine stretches).
void record_capture_binning_vs_raw_sqlite(benchmark::State& state) {
  const auto path = bench_file("-binning.sqlite");
  constexpr int passes = 5;
  std::vector<double> raw_wall, raw_cpu, our_wall, our_cpu;
  bool ok = true;
  for (auto _ : state) {
    for (int pass = 0; pass < passes; ++pass) {
      const auto raw = timed_pass(path, raw_sqlite_binning_pass, ok);
      const auto ours = timed_pass(path, capture_binning_pass, ok);
      raw_wall.push_back(raw.wall_s);
      raw_cpu.push_back(raw.cpu_s);
      our_wall.push_back(ours.wall_s);
      our_cpu.push_back(ours.cpu_s);
    }
  }
  remove_capture(path);
  if (!ok) {
    state.SkipWithError("a pass failed");
    return;
  }
  const auto median = [](std::vector<double> values) {
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
  };
  const double raw_rate = binning_samples / median(raw_wall);
  const double our_rate = binning_samples / median(our_wall);
  const double ratio = our_rate / raw_rate;
  const double cpu_ratio = median(raw_cpu) / median(our_cpu);
  state.counters["capture_samples_per_s"] = our_rate;
  state.counters["raw_sqlite_samples_per_s"] = raw_rate;
  state.counters["ratio"] = ratio;
  state.counters["cpu_ratio"] = cpu_ratio;
  std::printf(
      "capture of ULS binning (%zu targets): %.0f samples/s, raw sqlite3 C %.0f samples/s, ratio %.2f "
      "(goal >= 0.9): %s; CPU per pass %.0f ms vs %.0f ms, ratio %.2f\n",
      targets_per_sample, our_rate, raw_rate, ratio, ratio >= 0.9 ? "met" : "MISSED", median(our_cpu) * 1e3,
      median(raw_cpu) * 1e3, cpu_ratio);
}

}  // namespace

BENCHMARK(record_capture_binning_vs_raw_sqlite)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(record_fwrite_jsonl_baseline)->Unit(benchmark::kMillisecond);
BENCHMARK(record_capture_write)->Unit(benchmark::kMillisecond);
BENCHMARK(record_format_jsonl)->Unit(benchmark::kMillisecond);
BENCHMARK(record_format_csv)->Unit(benchmark::kMillisecond);
