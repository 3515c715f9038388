// `rangekit tap` in a line (docs/tap.md): what it adds to the time a chunk takes from one
// side to the other. The bench is both ends: it writes a reply-sized chunk as the sensor (a
// pty it made) and times its arrival at the host end (the tap's --host-pty), and the same
// chunk across one pty with no tap, same run; 1000 chunks each way at 500 Hz.
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "ls5_driver/cli_process.hpp"
#include "poll_until.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/sim/pty.hpp"
#include "service_rig.hpp"

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using ls5_driver_test::Child;
using rangekit::bench::percentile;
using rangekit::test::path_appears;

constexpr int chunks = 1000;
constexpr auto period = 2ms;
const std::string chunk = "$MU,1\r\n";  // a ULS reply: a frame the tap decodes on its way

// Times each chunk written to `from` until all of it is read from `to`, in ms.
std::vector<double> crossing_ms(rangekit::Transport& from, rangekit::Transport& to) {
  std::vector<double> times;
  std::array<std::uint8_t, 256> buffer{};
  auto next = Clock::now();
  for (int i = 0; i < chunks; ++i) {
    std::this_thread::sleep_until(next);
    next += period;
    const auto sent = Clock::now();
    if (!from.write_all(rangekit::as_bytes(chunk))) return {};
    std::size_t got = 0;
    while (got < chunk.size()) {
      auto read = to.read_some(buffer, 1000ms);
      if (!read || *read == 0) return {};  // lost: the row says none measured
      got += *read;
    }
    times.push_back(std::chrono::duration<double, std::milli>(Clock::now() - sent).count());
  }
  return times;
}

void BM_TapAddedLatency(benchmark::State& state) {
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores): the benchmark loop
    ls5_driver_test::TempDir dir;
    const rangekit::SerialSettings line{115200, rangekit::Parity::none, 1};
    // Without the tap: the chunk crosses one pty, master to slave.
    std::vector<double> direct;
    {
      auto sensor = rangekit::PseudoTerminal::open((dir.path / "direct").string());
      if (!sensor) return state.SkipWithError("no pty");
      auto host = rangekit::open_serial_link((dir.path / "direct").string(), line);
      if (!host) return state.SkipWithError("cannot open the pty");
      direct = crossing_ms(**sensor, **host);
    }
    // Through the tap: sensor pty -> tap -> the tap's host pty.
    auto sensor = rangekit::PseudoTerminal::open((dir.path / "sensor").string());
    if (!sensor) return state.SkipWithError("no pty");
    const std::string host_path = (dir.path / "host").string();
    Child tap({"tap", "uls", "--sensor", (dir.path / "sensor").string(), "--host-pty", host_path, "--baud", "115200",
               "--format", "jsonl"});
    std::thread drain([&] {
      while (!tap.read_line().empty()) {
      }
    });
    std::vector<double> to_host;
    std::vector<double> to_sensor;
    if (path_appears(host_path)) {
      auto host = rangekit::open_serial_link(host_path, line);
      if (host) {
        const double cpu_before = rangekit::bench::cpu_seconds(tap.pid());
        const auto started = Clock::now();
        to_host = crossing_ms(**sensor, **host);
        to_sensor = crossing_ms(**host, **sensor);
        const double seconds = std::chrono::duration<double>(Clock::now() - started).count();
        state.counters["tap_cpu_pct"] = 100.0 * (rangekit::bench::cpu_seconds(tap.pid()) - cpu_before) / seconds;
      }
    }
    tap.terminate();
    drain.join();
    tap.wait();
    if (direct.size() != chunks || to_host.size() != chunks || to_sensor.size() != chunks) {
      return state.SkipWithError("a chunk did not arrive");
    }
    state.counters["direct_p50_ms"] = percentile(direct, 50);
    state.counters["direct_p99_ms"] = percentile(direct, 99);
    state.counters["to_host_p50_ms"] = percentile(to_host, 50);
    state.counters["to_host_p99_ms"] = percentile(to_host, 99);
    state.counters["to_sensor_p99_ms"] = percentile(to_sensor, 99);
  }
}

// Moves `total` bytes of back-to-back replies from `from` to `to` as fast as both ends go: MB/s,
// 0 when they did not all arrive.
double megabytes_per_second(rangekit::Transport& from, rangekit::Transport& to, std::size_t total) {
  std::string block;
  while (block.size() < 4096) block += chunk;
  std::thread writer([&] {
    for (std::size_t sent = 0; sent < total; sent += block.size()) {
      if (!from.write_all(rangekit::as_bytes(block))) return;
    }
  });
  const auto started = Clock::now();
  std::size_t got = 0;
  std::array<std::uint8_t, 65536> buffer{};
  const std::size_t expected = (total + block.size() - 1) / block.size() * block.size();
  while (got < expected) {
    auto read = to.read_some(buffer, 1000ms);
    if (!read || *read == 0) break;
    got += *read;
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - started).count();
  writer.join();
  return got == expected ? static_cast<double>(got) / 1e6 / seconds : 0.0;
}

// The bytes a tap carries per second one way, against one pty without it, same run: 16 MB of
// ULS replies, which the tap decodes on the way (its report falls behind before the line does).
void BM_TapThroughput(benchmark::State& state) {
  constexpr std::size_t total = 16u << 20;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores): the benchmark loop
    ls5_driver_test::TempDir dir;
    const rangekit::SerialSettings line{115200, rangekit::Parity::none, 1};
    double direct = 0;
    {
      auto sensor = rangekit::PseudoTerminal::open((dir.path / "direct").string());
      if (!sensor) return state.SkipWithError("no pty");
      auto host = rangekit::open_serial_link((dir.path / "direct").string(), line);
      if (!host) return state.SkipWithError("cannot open the pty");
      direct = megabytes_per_second(**sensor, **host, total);
    }
    auto sensor = rangekit::PseudoTerminal::open((dir.path / "sensor").string());
    if (!sensor) return state.SkipWithError("no pty");
    const std::string host_path = (dir.path / "host").string();
    Child tap({"tap", "--family", "uls", "--sensor", (dir.path / "sensor").string(), "--host-pty", host_path, "--baud",
               "115200", "--format", "jsonl"});
    std::thread drain([&] {
      while (!tap.read_line().empty()) {
      }
    });
    double tapped = 0;
    if (path_appears(host_path)) {
      if (auto host = rangekit::open_serial_link(host_path, line)) {
        const double cpu_before = rangekit::bench::cpu_seconds(tap.pid());
        const auto started = Clock::now();
        tapped = megabytes_per_second(**sensor, **host, total);
        const double seconds = std::chrono::duration<double>(Clock::now() - started).count();
        state.counters["tap_cpu_pct"] = 100.0 * (rangekit::bench::cpu_seconds(tap.pid()) - cpu_before) / seconds;
      }
    }
    tap.terminate();
    drain.join();
    tap.wait();
    if (direct == 0 || tapped == 0) return state.SkipWithError("the bytes did not all arrive");
    state.counters["direct_MBps"] = direct;
    state.counters["tapped_MBps"] = tapped;
    state.counters["ratio"] = tapped / direct;
  }
}

}  // namespace

BENCHMARK(BM_TapThroughput)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK(BM_TapAddedLatency)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
