// Host streaming at the LS5's fastest rate (1000 records/s at 921600 baud, §8.4): the
// driver's stream against `cat` of the same pty, the emulator in its own process; records
// delivered, CPU and heap allocations per record (docs/performance.md, docs/host-ls5.md).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "allocation_counter.hpp"
#include "host_stream_rig.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/ls5/driver.hpp"

namespace {

using namespace std::chrono_literals;
using rangekit::bench::control;
using Clock = std::chrono::steady_clock;

constexpr std::uint32_t fast_baud = 921600;
constexpr double records_per_second = 1000;  // §8.4: 1 / (t n)
constexpr std::size_t record_bytes = 7;      // `!ddddd<CR>`, table 9.1
constexpr auto settle = 500ms;               // from ST to the window's start
constexpr auto window = 5s;

// One emulator for both benches (the same pty): started and set to t = 1 ms,
// n = 1, 921600 baud on first use; stopped at exit.
struct Ls5Rig {
  Ls5Rig();
  rangekit::bench::ScratchDir dir;
  std::optional<rangekit::cli::SimProcess> sim;
  std::string link = (dir.path() / "ls5").string();
  std::string socket = (dir.path() / "ls5.sock").string();
  std::string error;
};

Ls5Rig::Ls5Rig() {
  auto started = rangekit::bench::start_emulator(
      {"ls5", "--port", link, "--control", socket, "--version", "LS5.6.0", "--seed", "1"},
      (dir.path() / "ls5.log").string(), 10s);
  if (!started) {
    error = started.error().describe();
    return;
  }
  sim.emplace(std::move(started).value());
  // Factory settings talk at 115200 (table 9.2); the new baud applies after the echo (L28).
  auto port = rangekit::SerialPort::open(link, rangekit::SerialSettings{115200});
  if (!port) {
    error = port.error().describe();
    return;
  }
  {
    rangekit::ls5::Driver driver(std::move(port).value(), rangekit::ls5::DriverOptions{});
    for (const auto& [name, value] : {std::pair{"period-ms", "1"}, std::pair{"thinning", "1"}}) {
      if (auto done = driver.set(name, value); !done) {
        error = std::string(name) + ": " + done.error().describe();
        return;
      }
    }
    // The echo of W05 leaves at 115200; the sensor answers at 921600 after it (L28).
    if (auto done = driver.set("baud-rate", "921600"); !done) {
      error = "baud-rate: " + done.error().describe();
      return;
    }
  }
  auto fast = rangekit::SerialPort::open(link, rangekit::SerialSettings{fast_baud});
  if (!fast) {
    error = fast.error().describe();
    return;
  }
  rangekit::ls5::Driver driver(std::move(fast).value(), rangekit::ls5::DriverOptions{});
  auto baud = driver.get("baud-rate");
  if (!baud || baud->text != "921600") {
    error = "the LS5 does not answer at 921600 after W0508: " + (baud ? baud->text : baud.error().describe());
  }
}

Ls5Rig& ls5_rig() {
  static Ls5Rig rig;
  return rig;
}

struct DeviceCount {
  std::uint64_t measurements = 0;
  std::uint64_t dropped_output_bytes = 0;  // the runtime found the pty full (host not reading)
};

rangekit::Result<DeviceCount> device_count(const Ls5Rig& rig) {
  auto outputs = control(rig.socket, {{"cmd", "outputs"}});
  if (!outputs) return std::move(outputs).error();
  auto status = control(rig.socket, {{"cmd", "status"}});
  if (!status) return std::move(status).error();
  return DeviceCount{outputs->value("measurements", std::uint64_t{0}),
                     status->value("dropped_output_bytes", std::uint64_t{0})};
}

// A point of the window: the device's count and the host's, taken right after the reply.
struct Mark {
  DeviceCount device;
  std::uint64_t host_records = 0;
  Clock::time_point at;
};

void report(rangekit::bench::HostFigures& counters, const Mark& first, const Mark& last, double cpu_s, double stream_s,
            double lost) {
  const double window_s = std::chrono::duration<double>(last.at - first.at).count();
  const auto sent = static_cast<double>(last.device.measurements - first.device.measurements);
  const auto received = static_cast<double>(last.host_records - first.host_records);
  counters["window_s"] = window_s;
  counters["dev_records"] = sent;  // n = 1: every measurement is streamed
  counters["rate_records"] = records_per_second * window_s;
  counters["host_records"] = received;
  counters["delivered_pct"] = 100.0 * received / sent;
  counters["host_rec_per_s"] = received / window_s;
  counters["wire_pct"] = 100.0 * received * record_bytes / window_s / (fast_baud / 10.0);
  counters["lost"] = lost;
  counters["pty_dropped_B"] = static_cast<double>(last.device.dropped_output_bytes - first.device.dropped_output_bytes);
  counters["host_cpu_pct"] = 100.0 * cpu_s / stream_s;
}

std::string run_driver(Ls5Rig& rig, rangekit::bench::HostFigures& counters) {
  auto port = rangekit::SerialPort::open(rig.link, rangekit::SerialSettings{fast_baud});
  if (!port) return port.error().describe();

  const auto started = Clock::now();
  const double cpu_before = rangekit::bench::process_cpu_s();
  rangekit::ls5::Driver driver(std::move(port).value(), rangekit::ls5::DriverOptions{});
  auto opened = driver.start_stream({});
  if (!opened) return opened.error().describe();
  auto& stream = **opened;
  std::uint64_t consumed = 0;
  std::optional<Mark> first;
  std::optional<Mark> last;
  std::vector<rangekit::StreamItem> batch;
  std::uint64_t allocations_at_first = 0;
  std::uint64_t allocations_in_window = 0;
  std::uint64_t records_in_window = 0;
  while (!last) {
    if (stream.next_batch(batch, 50ms)) {
      for (const auto& item : batch) {
        if (std::holds_alternative<rangekit::Sample>(item)) ++consumed;
      }
    }
    const auto now = Clock::now();
    if (first ? now < first->at + window : now < started + settle) continue;
    if (first) {
      allocations_in_window = rangekit::bench::allocation_count() - allocations_at_first;
      records_in_window = stream.records() - first->host_records;
    }
    auto count = device_count(rig);
    if (!count) return count.error().describe();
    (first ? last : first) = Mark{*count, stream.records(), Clock::now()};
    allocations_at_first = rangekit::bench::allocation_count();
  }
  stream.stop();  // SB
  while (auto item = stream.next(0ms)) {
    if (std::holds_alternative<rangekit::Sample>(*item)) ++consumed;
  }
  const double stream_s = std::chrono::duration<double>(Clock::now() - started).count();
  const double cpu_s = rangekit::bench::process_cpu_s() - cpu_before;
  report(counters, *first, *last, cpu_s, stream_s, static_cast<double>(stream.lost()));
  counters["consumed"] = static_cast<double>(consumed);
  counters["records"] = static_cast<double>(stream.records());
  counters["allocs_in_window"] = static_cast<double>(allocations_in_window);
  counters["records_in_window"] = static_cast<double>(records_in_window);
  counters["allocs_per_record"] =
      static_cast<double>(allocations_in_window) / static_cast<double>(std::max<std::uint64_t>(records_in_window, 1));
  return {};
}

// The floor: `cat` of the same pty into a file; ST and SB written to the pty.
std::string run_cat(Ls5Rig& rig, rangekit::bench::HostFigures& counters) {
  std::optional<Mark> first;
  std::optional<Mark> last;
  auto ran = rangekit::bench::cat_window(  // SB is answered by its echo (table 9.1)
      rig.link, rig.dir.path() / "cat.out", fast_baud, "#01ST\r", "#01SB\r", "!01SB\r", settle, window,
      [&](std::uintmax_t file_bytes) -> rangekit::Status {
        auto count = device_count(rig);
        if (!count) return std::move(count).error();
        (first ? last : first) = Mark{*count, file_bytes / record_bytes, Clock::now()};
        return rangekit::ok_status();
      });
  if (!ran) return ran.error().describe();
  const std::string& copied = ran->copied;
  std::uint64_t records = 0;
  for (std::size_t at = copied.find('!'); at != std::string::npos; at = copied.find('!', at + 1)) {
    const bool digits = at + record_bytes <= copied.size() && copied[at + record_bytes - 1] == '\r' &&
                        copied.find_first_not_of("0123456789", at + 1) == at + record_bytes - 1;
    if (digits) ++records;
  }
  report(counters, *first, *last, ran->cpu_s, ran->stream_s, 0);
  counters["records"] = static_cast<double>(records);
  return {};
}

void BM_Ls5StreamAndCat1kHz921600(benchmark::State& state) {
  auto& rig = ls5_rig();  // first use: the emulator starts (outside the timed loop)
  if (!rig.error.empty()) return state.SkipWithError(rig.error.c_str());
  for (auto _ : state) {
    rangekit::bench::run_paired(
        state, [&rig](rangekit::bench::HostFigures& figures) { return run_driver(rig, figures); },
        [&rig](rangekit::bench::HostFigures& figures) { return run_cat(rig, figures); });
  }
}

}  // namespace

BENCHMARK(BM_Ls5StreamAndCat1kHz921600)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
