// CPU cost of the ULS firmware model per simulated second: one unit averaging
// at 5000 PRF, and 64 units on one bus (issue 4). Time is virtual, so the
// benchmark's real time is the CPU the emulator needs.
#include <benchmark/benchmark.h>

#include <memory>
#include <string_view>
#include <vector>

#include "../src/uls/emulator/firmware.hpp"  // internal header; bench/ has no src/ include path

namespace {

using rangekit::LineByte;
using rangekit::Nanos;
using namespace rangekit::uls::emulator;

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

}  // namespace

BENCHMARK(BM_UlsOneUnit5000PrfPerSimulatedSecond)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Uls64UnitsBusPerSimulatedSecond)->Unit(benchmark::kMillisecond);
