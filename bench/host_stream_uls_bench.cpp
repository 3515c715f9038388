// Host streaming at the ULS's fastest serial output: binning bursts of 15 targets (§9's
// worst case) back to back at 230400 baud (U19, U39), the driver's stream against `cat` of
// the same pty; bursts delivered, CPU and heap allocations per burst (docs/host-uls.md).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "allocation_counter.hpp"
#include "host_stream_rig.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/uls/driver.hpp"
#include "rangekit/uls/family.hpp"

namespace {

using namespace std::chrono_literals;
using rangekit::bench::control;
using Clock = std::chrono::steady_clock;

constexpr std::uint32_t fast_baud = 230400;  // BR maximum (§8, §9 serial command maximum)
constexpr double u19_chars_per_s = fast_baud / 11.52;
constexpr double wire_8n1_bytes_per_s = fast_baud / 10.0;
constexpr std::uint32_t binning_prf = 1000;
constexpr std::uint32_t binning_ppm = 25;
constexpr std::uint32_t bin_hits = 2;
constexpr int scene_targets = 15;
constexpr auto settle = 500ms;
constexpr auto window = 5s;

// Fifteen white targets 1 m to 11.5 m, inside the 13 m of 1-inch bins (BS 0),
// no noise hits or dust so every burst holds exactly the fifteen.
std::string scene_toml() {
  std::string text = "dust = 0\nambient_noise = 0\n";
  for (int i = 0; i < scene_targets; ++i) {
    text += "\n[[targets]]\ndistance_m = " + std::to_string(1.0 + 0.75 * i) + "\nreflectivity = 0.9\n";
  }
  return text;
}

// One emulator for both benches (the same pty), configured on first use.
struct UlsRig {
  UlsRig();
  rangekit::bench::ScratchDir dir;
  std::optional<rangekit::cli::SimProcess> sim;
  std::string link = (dir.path() / "uls").string();
  std::string socket = (dir.path() / "uls.sock").string();
  std::string error;
};

rangekit::Status configure(const std::string& link) {
  // Factory: averaging, measurement output on the configuration port, 115200 (U35).
  auto port = rangekit::SerialPort::open(link, rangekit::SerialSettings{115200});
  if (!port) return std::move(port).error();
  rangekit::uls::Driver uls(std::move(port).value());
  if (auto done = uls.set_mode(rangekit::uls::Mode::binning); !done) return done;
  auto prf = uls.prf();
  if (!prf) return std::move(prf).error();
  if (auto done = uls.set_prf((*prf)[0], binning_prf, (*prf)[2]); !done) return done;
  auto ppm = uls.pulses_per_measurement();
  if (!ppm) return std::move(ppm).error();
  if (auto done = uls.set_pulses_per_measurement((*ppm)[0], binning_ppm); !done) return done;
  if (auto done = uls.set_bin_size(rangekit::uls::BinSize::inch_1); !done) return done;
  if (auto done = uls.set_bin_threshold(bin_hits); !done) return done;
  if (auto done = uls.set_output_port(rangekit::uls::OutputPort::universal_rs232); !done) return done;
  if (auto done = uls.set_continuous(true); !done) return done;
  // The $OK leaves at 115200, then the port runs at 230400 (U36).
  return uls.set_baud(rangekit::uls::BaudPort::output, fast_baud);
}

UlsRig::UlsRig() {
  const auto scene = dir.path() / "scene.toml";
  std::ofstream(scene) << scene_toml();
  auto started = rangekit::bench::start_emulator(
      {"uls", "--port", link, "--control", socket, "--scene", scene.string(), "--seed", "1"},
      (dir.path() / "uls.log").string(), 10s);
  if (!started) {
    error = started.error().describe();
    return;
  }
  sim.emplace(std::move(started).value());
  if (auto done = configure(link); !done) error = "configuring the ULS: " + done.error().describe();
}

UlsRig& uls_rig() {
  static UlsRig rig;
  return rig;
}

struct DeviceCount {
  std::uint64_t bursts_on_wire = 0;  // measurements - skipped (U39)
  std::uint64_t measurements = 0;
  std::uint64_t restarts = 0;
  std::uint64_t dropped_output_bytes = 0;
};

rangekit::Result<DeviceCount> device_count(const UlsRig& rig) {
  auto outputs = control(rig.socket, {{"cmd", "outputs"}});
  if (!outputs) return std::move(outputs).error();
  auto status = control(rig.socket, {{"cmd", "status"}});
  if (!status) return std::move(status).error();
  const nlohmann::json& unit = outputs->contains("devices") ? outputs->at("devices").at(0) : *outputs;
  DeviceCount count;
  count.measurements = unit.value("measurements", std::uint64_t{0});
  count.bursts_on_wire = count.measurements - unit.value("skipped_lines", std::uint64_t{0});
  count.restarts = unit.value("binning_restarts", std::uint64_t{0});
  count.dropped_output_bytes = status->value("dropped_output_bytes", std::uint64_t{0});
  return count;
}

struct Mark {
  DeviceCount device;
  std::uint64_t host_bursts = 0;
  std::uint64_t host_lines = 0;
  std::uint64_t host_bytes = 0;
  Clock::time_point at;
};

void report(rangekit::bench::HostFigures& counters, const Mark& first, const Mark& last, double cpu_s, double stream_s,
            double lost) {
  const double window_s = std::chrono::duration<double>(last.at - first.at).count();
  const auto sent = static_cast<double>(last.device.bursts_on_wire - first.device.bursts_on_wire);
  const auto bursts = static_cast<double>(last.host_bursts - first.host_bursts);
  const auto bytes = static_cast<double>(last.host_bytes - first.host_bytes);
  counters["window_s"] = window_s;
  counters["dev_bursts"] = sent;
  counters["dev_offered"] = static_cast<double>(last.device.measurements - first.device.measurements);
  counters["host_bursts"] = bursts;
  counters["host_lines"] = static_cast<double>(last.host_lines - first.host_lines);
  counters["delivered_pct"] = 100.0 * bursts / sent;
  counters["host_B_per_s"] = bytes / window_s;
  counters["wire_pct_u19"] = 100.0 * bytes / window_s / u19_chars_per_s;
  counters["wire_pct_8n1"] = 100.0 * bytes / window_s / wire_8n1_bytes_per_s;
  counters["lost"] = lost;
  counters["pty_dropped_B"] = static_cast<double>(last.device.dropped_output_bytes - first.device.dropped_output_bytes);
  counters["host_cpu_pct"] = 100.0 * cpu_s / stream_s;
}

std::string run_driver(UlsRig& rig, rangekit::bench::HostFigures& counters) {
  auto port = rangekit::SerialPort::open(rig.link, rangekit::SerialSettings{fast_baud});
  if (!port) return port.error().describe();
  auto bytes = std::make_shared<std::atomic<std::uint64_t>>(0);

  const auto started = Clock::now();
  const double cpu_before = rangekit::bench::process_cpu_s();
  rangekit::uls::Driver uls(std::make_unique<rangekit::bench::CountingTransport>(std::move(port).value(), bytes));
  auto stream = uls.start_stream(rangekit::uls::StreamMode::continuous);
  if (!stream) return stream.error().describe();
  std::uint64_t bursts = 0;
  std::uint64_t targets = 0;
  std::uint64_t short_bursts = 0;
  std::optional<Mark> first;
  std::optional<Mark> last;
  std::vector<rangekit::StreamItem> batch;
  std::uint64_t allocations_at_first = 0;
  std::uint64_t allocations_in_window = 0;
  std::uint64_t bursts_in_window = 0;
  while (!last) {
    if ((*stream)->next_batch(batch, 50ms)) {
      for (const auto& item : batch) {
        if (const auto* sample = std::get_if<rangekit::Sample>(&item);
            sample != nullptr && sample->kind == rangekit::uls::kind::binning) {
          ++bursts;
          targets += sample->targets.size();
          if (sample->targets.size() != static_cast<std::size_t>(scene_targets)) ++short_bursts;
        }
      }
    }
    const auto now = Clock::now();
    if (first ? now < first->at + window : now < started + settle) continue;
    if (first) {
      allocations_in_window = rangekit::bench::allocation_count() - allocations_at_first;
      bursts_in_window = bursts - first->host_bursts;
    }
    auto count = device_count(rig);
    if (!count) return count.error().describe();
    (first ? last : first) = Mark{*count, bursts, uls.counters().measurements, bytes->load(), Clock::now()};
    allocations_at_first = rangekit::bench::allocation_count();
  }
  (*stream)->stop(rangekit::uls::AfterStream::stop_measuring);  // ST
  const double stream_s = std::chrono::duration<double>(Clock::now() - started).count();
  const double cpu_s = rangekit::bench::process_cpu_s() - cpu_before;
  report(counters, *first, *last, cpu_s, stream_s, static_cast<double>((*stream)->lost()));
  counters["targets_per_burst"] = static_cast<double>(targets) / static_cast<double>(bursts);
  counters["short_bursts"] = static_cast<double>(short_bursts);
  counters["bad_frames"] = static_cast<double>(uls.counters().bad_frames);
  counters["allocs_in_window"] = static_cast<double>(allocations_in_window);
  counters["records_in_window"] = static_cast<double>(bursts_in_window);
  counters["allocs_per_record"] =
      static_cast<double>(allocations_in_window) / static_cast<double>(std::max<std::uint64_t>(bursts_in_window, 1));
  return {};
}

// Counts `$BM` lines and complete bursts (index = count - 1) whose <CR> lies in [from, to).
struct LineCount {
  std::uint64_t lines = 0;
  std::uint64_t bursts = 0;
};
LineCount count_lines(const std::string& text, std::size_t from, std::size_t to) {
  LineCount count;
  std::size_t start = 0;
  for (std::size_t end = text.find('\r'); end != std::string::npos; end = text.find('\r', start)) {
    const std::string_view line(text.data() + start, end - start);
    start = end + 1;
    if (end < from || end >= to || !line.starts_with("$BM,")) continue;
    ++count.lines;
    const auto index = std::strtoul(line.data() + 4, nullptr, 10);
    const auto comma = line.find(',', 4);
    if (comma == std::string_view::npos) continue;
    const auto targets = std::strtoul(line.data() + comma + 1, nullptr, 10);
    if (targets > 0 && index + 1 == targets) ++count.bursts;
  }
  return count;
}

// The floor: `cat` of the same pty into a file; GO and ST written to the pty.
std::string run_cat(UlsRig& rig, rangekit::bench::HostFigures& counters) {
  std::optional<Mark> first;
  std::optional<Mark> last;
  auto ran = rangekit::bench::cat_window(rig.link, rig.dir.path() / "cat.out", fast_baud, "$GO\r", "$ST\r", "$OK\r",
                                         settle, window, [&](std::uintmax_t file_bytes) -> rangekit::Status {
                                           auto count = device_count(rig);
                                           if (!count) return std::move(count).error();
                                           (first ? last : first) = Mark{*count, 0, 0, file_bytes, Clock::now()};
                                           return rangekit::ok_status();
                                         });
  if (!ran) return ran.error().describe();
  const auto in_window = count_lines(ran->copied, first->host_bytes, last->host_bytes);
  first->host_bursts = 0;
  last->host_bursts = in_window.bursts;
  last->host_lines = in_window.lines;
  report(counters, *first, *last, ran->cpu_s, ran->stream_s, 0);
  const auto all = count_lines(ran->copied, 0, ran->copied.size());
  counters["targets_per_burst"] = static_cast<double>(all.lines) / static_cast<double>(all.bursts);
  return {};
}

void BM_UlsStreamAndCatBinning230400(benchmark::State& state) {
  auto& rig = uls_rig();  // first use: the emulator starts (outside the timed loop)
  if (!rig.error.empty()) return state.SkipWithError(rig.error.c_str());
  for (auto _ : state) {
    rangekit::bench::run_paired(
        state, [&rig](rangekit::bench::HostFigures& figures) { return run_driver(rig, figures); },
        [&rig](rangekit::bench::HostFigures& figures) { return run_cat(rig, figures); });
  }
}

}  // namespace

BENCHMARK(BM_UlsStreamAndCatBinning230400)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
