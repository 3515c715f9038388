// ULS emulator figures (docs/emulator-uls.md): CPU per simulated second (one unit, and 64 on
// a bus), output rate against PRF/PPM beside a naive sleep-loop ticker, and byte pacing
// against the baud rate beside an unpaced pty.
#include <benchmark/benchmark.h>

#include <array>
#include <atomic>
#include <cmath>
#include <memory>
#include <string_view>
#include <thread>
#include <vector>

#include "rangekit/core/serial_port.hpp"
#include "rangekit/sim/emulator_runtime.hpp"
#include "rangekit/sim/pty.hpp"
#include "rangekit/uls/emulator/firmware.hpp"

namespace {

using rangekit::LineByte;
using rangekit::Nanos;
using namespace rangekit::uls::emulator;
using SteadyTime = std::chrono::steady_clock::time_point;

void send(Firmware& unit, std::string_view text, Nanos now) {
  for (const char c : text) unit.receive(configuration_port, static_cast<std::uint8_t>(c), now);
}

// Runs `units` to `until` deadline by deadline, as the runtime does.
void run(std::vector<std::unique_ptr<Firmware>>& units, Nanos& now, Nanos until, std::vector<LineByte>& sink) {
  while (true) {
    Nanos next = Nanos::max();
    for (const auto& unit : units) next = std::min(next, unit->next_deadline());
    if (next > until) break;
    now = std::max(now, next);
    for (auto& unit : units) {
      unit->advance(now);
      unit->take_line_output(configuration_port, now, sink);
      unit->take_line_output(universal_port, now, sink);
    }
    sink.clear();
  }
  now = until;
}

void simulate(benchmark::State& state, std::size_t count) {
  std::vector<std::unique_ptr<Firmware>> units;
  Nanos now{0};
  for (std::size_t i = 0; i < count; ++i) {
    FirmwareOptions options;
    options.seed = static_cast<std::uint32_t>(i + 1);
    options.address = static_cast<std::uint8_t>(0x30 + i);
    units.push_back(std::make_unique<Firmware>(std::move(options)));
    send(*units.back(), "$PF,5000\r$GO\r", now);
  }
  std::vector<LineByte> sink;
  for (auto _ : state) run(units, now, now + std::chrono::seconds(1), sink);
  state.counters["simulated_s_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_UlsOneUnit5000PrfPerSimulatedSecond(benchmark::State& state) { simulate(state, 1); }
void BM_Uls64UnitsBusPerSimulatedSecond(benchmark::State& state) { simulate(state, 64); }

// Output rate over 60 s of simulated time (goal: within 0.01 % of
// PRF / PPM). The rate comes from the time stamps of the lines' CRs, first to
// last, so it resolves far below one line in 6250.
void BM_UlsOutputRateOverSixtySimulatedSeconds(benchmark::State& state) {
  constexpr double prf = 5000;
  constexpr double ppm = 48;
  double measured_hz = 0;
  std::size_t lines = 0;
  for (auto _ : state) {
    FirmwareOptions options;
    options.seed = 7;
    Firmware unit(std::move(options));
    Nanos now{0};
    send(unit, "$PF,5000\r$AW,40\r$PO,48\r$GO\r", now);
    std::vector<LineByte> out;
    std::vector<Nanos> ends;
    const Nanos until = now + std::chrono::seconds(60);
    while (true) {
      const Nanos next = unit.next_deadline();
      if (next > until) break;
      now = std::max(now, next);
      unit.advance(now);
      out.clear();
      unit.take_line_output(configuration_port, now, out);
      for (const auto& byte : out) {
        if (byte.value == '\r') ends.push_back(byte.done);
      }
    }
    // The first lines answer the commands ($OK); measurements follow.
    const std::size_t first = std::min<std::size_t>(4, ends.size());
    lines = ends.size() - first;
    if (lines < 2) {
      state.SkipWithError("no measurement lines");
      return;
    }
    const double span_s = std::chrono::duration<double>(ends.back() - ends[first]).count();
    measured_hz = static_cast<double>(lines - 1) / span_s;
  }
  const double expected_hz = prf / ppm;
  state.counters["lines"] = static_cast<double>(lines);
  state.counters["measured_hz"] = measured_hz;
  state.counters["expected_hz"] = expected_hz;
  state.counters["error_pct"] = 100.0 * (measured_hz - expected_hz) / expected_hz;
}

// Least-squares slope of y against x: events per second from (time, count) pairs, so
// the scheduling jitter of single reads averages out instead of sitting at both ends.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  const auto n = static_cast<double>(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// Lines per second from the lower envelope of arrival times: in each of `windows` slices
// the line that arrived earliest relative to the nominal schedule (the least OS delay on
// a loaded machine), then the least-squares slope through those points.
double envelope_rate(const std::vector<double>& times, double nominal_hz, std::size_t windows) {
  std::vector<double> best_index(windows, -1);
  std::vector<double> best_time(windows, 0);
  std::vector<double> best_residual(windows, 1e300);
  const double span = times.back() - times.front();
  for (std::size_t i = 0; i < times.size(); ++i) {
    auto w = static_cast<std::size_t>((times[i] - times.front()) / span * static_cast<double>(windows));
    w = std::min(w, windows - 1);
    const double residual = times[i] - static_cast<double>(i) / nominal_hz;
    if (residual < best_residual[w]) {
      best_residual[w] = residual;
      best_index[w] = static_cast<double>(i);
      best_time[w] = times[i];
    }
  }
  std::vector<double> x;
  std::vector<double> y;
  for (std::size_t w = 0; w < windows; ++w) {
    if (best_index[w] < 0) continue;
    x.push_back(best_time[w]);
    y.push_back(best_index[w]);
  }
  return slope(x, y);
}

double seconds_since(SteadyTime start, SteadyTime t) { return std::chrono::duration<double>(t - start).count(); }

// One unit on the real clock, its universal port on a pty, set up with `commands`
// (through the configuration port, which no host reads) before the runtime serves.
struct RealClockUnit {
  std::unique_ptr<Firmware> unit;
  std::unique_ptr<rangekit::EmulatorRuntime> runtime;
  std::unique_ptr<rangekit::SerialPort> host;
  std::atomic<bool> stop{false};
  std::thread loop;

  bool start(std::string_view commands, std::uint32_t host_baud) {
    unit = std::make_unique<Firmware>(FirmwareOptions{});
    rangekit::LineConfig line{"universal", std::nullopt, {rangekit::LineAttachment{unit.get(), universal_port}}};
    auto created = rangekit::EmulatorRuntime::create({line}, rangekit::RuntimeOptions{});
    if (!created) return false;
    runtime = std::move(*created);
    send(*unit, commands, runtime->now());
    auto opened = rangekit::SerialPort::open(runtime->line_path(0),
                                             rangekit::SerialSettings{host_baud, rangekit::Parity::none, 1});
    if (!opened) return false;
    host = std::move(*opened);
    loop = std::thread([this] { (void)runtime->run(stop); });
    return true;
  }
  ~RealClockUnit() {
    stop = true;
    if (loop.joinable()) loop.join();
  }
};

// (a) Output rate: 4999 PRF / 48 PPM = 104.146 lines/s (not a whole number of ns per
// line), range only on the universal port, over 10 s of real time.
void BM_UlsOutputRateOverTenRealSeconds(benchmark::State& state) {
  constexpr double prf = 4999.0;
  constexpr double ppm = 48.0;
  constexpr double expected_hz = prf / ppm;
  constexpr double run_s = 10.0;
  for (auto _ : state) {
    RealClockUnit rig;
    if (!rig.start("$AW,7\r$PO,48\r$PF,4999\r$DM,1\r$MO,1\r$GO\r", 115200)) {
      state.SkipWithError("cannot start the emulator on a pty");
      return;
    }
    // Baseline in the same run and under the same load: a ticker that sleeps one period
    // per line, as a naive emulator would.
    std::vector<double> tick_times;
    std::vector<double> tick_counts;
    const SteadyTime start = std::chrono::steady_clock::now();
    std::thread ticker([&] {
      const auto period = std::chrono::duration_cast<Nanos>(std::chrono::duration<double>(1.0 / expected_hz));
      while (seconds_since(start, std::chrono::steady_clock::now()) < run_s) {
        std::this_thread::sleep_for(period);
        tick_times.push_back(seconds_since(start, std::chrono::steady_clock::now()));
        tick_counts.push_back(static_cast<double>(tick_counts.size()));
      }
    });
    std::vector<double> line_times;
    std::vector<double> line_counts;
    std::array<std::uint8_t, 256> buffer{};
    while (seconds_since(start, std::chrono::steady_clock::now()) < run_s) {
      auto got = rig.host->read_some(buffer, std::chrono::milliseconds(100));
      if (!got) continue;
      const double t = seconds_since(start, std::chrono::steady_clock::now());
      for (std::size_t i = 0; i < *got; ++i) {
        if (buffer[i] != '\r') continue;
        line_times.push_back(t);
        line_counts.push_back(static_cast<double>(line_counts.size()));
      }
    }
    ticker.join();
    if (line_times.size() < 100) {
      state.SkipWithError("too few lines arrived");
      return;
    }
    const double fitted = slope(line_times, line_counts);
    const double measured = envelope_rate(line_times, expected_hz, 20);
    const double baseline = slope(tick_times, tick_counts);
    state.counters["fit_all_lines_hz"] = fitted;
    state.counters["fit_all_error_pct"] = 100.0 * (fitted - expected_hz) / expected_hz;
    state.counters["expected_hz"] = expected_hz;
    state.counters["measured_hz"] = measured;
    state.counters["error_pct"] = 100.0 * (measured - expected_hz) / expected_hz;
    state.counters["baseline_sleep_loop_hz"] = baseline;
    state.counters["baseline_error_pct"] = 100.0 * (baseline - expected_hz) / expected_hz;
    state.counters["lines"] = static_cast<double>(line_times.size());
    state.counters["real_s"] = run_s;
  }
}

// Bytes per second a pty carries when nothing paces them: write blocks, read them back.
double unpaced_pty_bytes_per_second(std::uint32_t baud) {
  auto pty = rangekit::PseudoTerminal::open(std::nullopt);
  if (!pty) return 0;
  auto reader =
      rangekit::SerialPort::open((*pty)->public_path(), rangekit::SerialSettings{baud, rangekit::Parity::none, 1});
  if (!reader) return 0;
  const std::vector<std::uint8_t> block(1024, 'x');
  std::array<std::uint8_t, 4096> buffer{};
  double moved = 0;
  const SteadyTime start = std::chrono::steady_clock::now();
  while (seconds_since(start, std::chrono::steady_clock::now()) < 0.2) {
    if (!(*pty)->write_all(rangekit::Bytes(block.data(), block.size()))) break;
    std::size_t left = block.size();
    while (left > 0) {
      auto got = (*reader)->read_some(buffer, std::chrono::milliseconds(100));
      if (!got) return 0;
      left -= std::min(left, *got);
      moved += static_cast<double>(*got);
    }
  }
  return moved / seconds_since(start, std::chrono::steady_clock::now());
}

// (b) Byte pacing: 5000 PRF / 2 PPM keeps the universal port saturated, so the reader
// sees the UART's byte rate. The ULS character is 11.52 bit times (U19), so the expected
// rate is baud / 11.52; baud / 10 (a plain 8N1 line) is printed for comparison.
void BM_UlsBytePacing(benchmark::State& state) {
  const auto baud = static_cast<std::uint32_t>(state.range(0));
  const double expected = static_cast<double>(baud) / 11.52;
  constexpr double run_s = 2.5;
  for (auto _ : state) {
    RealClockUnit rig;
    const std::string setup = "$BR,1," + std::to_string(baud) + "\r$AW,1\r$PO,2\r$PF,5000\r$DM,2\r$MO,1\r$GO\r";
    if (!rig.start(setup, baud)) {
      state.SkipWithError("cannot start the emulator on a pty");
      return;
    }
    std::vector<double> times;
    std::vector<double> bytes;
    double total = 0;
    std::array<std::uint8_t, 4096> buffer{};
    const SteadyTime start = std::chrono::steady_clock::now();
    while (seconds_since(start, std::chrono::steady_clock::now()) < run_s) {
      auto got = rig.host->read_some(buffer, std::chrono::milliseconds(100));
      if (!got) continue;
      total += static_cast<double>(*got);
      const double t = seconds_since(start, std::chrono::steady_clock::now());
      if (t > 0.2) {  // past the baud switch and the first line
        times.push_back(t);
        bytes.push_back(total);
      }
    }
    // Baseline: the same pty carrying bytes nobody paces (how fast a pty goes by itself).
    const double unpaced = unpaced_pty_bytes_per_second(baud);
    if (times.size() < 10) {
      state.SkipWithError("too few reads");
      return;
    }
    const double measured = slope(times, bytes);
    state.counters["baud"] = baud;
    state.counters["expected_Bps"] = expected;
    state.counters["measured_Bps"] = measured;
    state.counters["error_pct"] = 100.0 * (measured - expected) / expected;
    state.counters["vs_baud_over_10_pct"] = 100.0 * (measured - baud / 10.0) / (baud / 10.0);
    state.counters["baseline_unpaced_pty_Bps"] = unpaced;
  }
}

}  // namespace

BENCHMARK(BM_UlsOneUnit5000PrfPerSimulatedSecond)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Uls64UnitsBusPerSimulatedSecond)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UlsOutputRateOverSixtySimulatedSeconds)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UlsOutputRateOverTenRealSeconds)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK(BM_UlsBytePacing)
    ->Arg(9600)
    ->Arg(38400)
    ->Arg(115200)
    ->Arg(230400)
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();
