// LS5 emulator cost (docs/emulator-ls5.md): CPU time per simulated second with a 1 kHz
// serial stream at 115200 baud (goal: under 5 % of a core, i.e. < 50 ms per
// simulated second), and UDP packets per second at 1 kHz on an Ethernet model.
#include <benchmark/benchmark.h>

#include <chrono>

// The firmware header is internal to src/ (bench/ has no src include path).
#include "rangekit/ls5/emulator/firmware.hpp"

namespace {

using namespace std::chrono_literals;
namespace emu = rangekit::ls5::emulator;

std::unique_ptr<emu::Firmware> make_firmware(const std::string& version, std::uint64_t* packets) {
  emu::FirmwareConfig config;
  config.version_text = version;
  config.scene.target = rangekit::Motion::constant_speed(10, 1.0);
  config.scene.target_set = true;
  if (packets != nullptr) {
    config.udp_sink = [packets](const emu::UdpDatagram&) {
      ++*packets;
      return rangekit::ok_status();
    };
  }
  auto firmware = emu::Firmware::create(std::move(config));
  if (!firmware) return nullptr;
  auto fw = std::move(*firmware);
  for (const char* command : {"#01W060A\r", "#01W0700\r", "#01ST\r"}) {  // t = 1 ms, stream on
    for (const char* c = command; *c != 0; ++c) fw->receive(0, static_cast<std::uint8_t>(*c), rangekit::Nanos{0});
  }
  return fw;
}

// Runs the firmware the way the runtime does: to each deadline, collecting the line output.
std::size_t run(emu::Firmware& fw, rangekit::Nanos from, rangekit::Nanos to, std::vector<rangekit::LineByte>& out) {
  rangekit::Nanos now = from;
  std::size_t bytes = 0;
  while (true) {
    const rangekit::Nanos deadline = fw.next_deadline();
    if (deadline > to) break;
    now = std::max(now, deadline);
    fw.advance(now);
    out.clear();
    fw.take_line_output(0, now, out);
    bytes += out.size();
  }
  return bytes;
}

void BM_Ls5Emulator_SimulatedSecondAt1kHz(benchmark::State& state) {
  auto fw = make_firmware("LS5.9.0", nullptr);
  std::vector<rangekit::LineByte> out;
  rangekit::Nanos now{0};
  std::size_t bytes = 0;
  for (auto _ : state) {
    bytes += run(*fw, now, now + 1s, out);
    now += 1s;
  }
  state.counters["records_per_sim_s"] =
      static_cast<double>(fw->records_sent()) / static_cast<double>(state.iterations());
  state.counters["skipped"] = static_cast<double>(fw->records_skipped());
  state.counters["line_bytes_per_sim_s"] = static_cast<double>(bytes) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_Ls5Emulator_SimulatedSecondAt1kHz)->Unit(benchmark::kMillisecond);

void BM_Ls5Emulator_UdpPacketsAt1kHz(benchmark::State& state) {
  std::uint64_t packets = 0;
  auto fw = make_firmware("LS5.12.0", &packets);
  std::vector<rangekit::LineByte> out;
  rangekit::Nanos now{0};
  for (auto _ : state) {
    run(*fw, now, now + 1s, out);
    now += 1s;
  }
  state.counters["packets_per_sim_s"] = static_cast<double>(packets) / static_cast<double>(state.iterations());
  state.counters["packets_per_cpu_s"] = benchmark::Counter(static_cast<double>(packets), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Ls5Emulator_UdpPacketsAt1kHz)->Unit(benchmark::kMillisecond);

}  // namespace
