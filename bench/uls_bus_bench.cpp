// RS-485 polling against the wire (docs/performance.md, "RS-485 polling"): a bus of N emulated
// ULS units, each measuring faster than one bus cycle (PPM 10 at PRF 5000: a reading every
// 2 ms), polled in turn with US and BM by uls::Bus, as `uls bus poll --measure` and the
// service's bus session do. The wire's minimum for the same polls, from the bytes that went
// each way: requests at 10 bits a byte, replies at the unit's 11.52 (U19), and the unit's
// 1 ms turnaround before each reply (U133).
#include <benchmark/benchmark.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "host_stream_rig.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/uls/bus.hpp"

namespace {

using Clock = std::chrono::steady_clock;

constexpr double turnaround_s = 0.001;    // the emulator's default (U133)
constexpr double reply_bits = 11.52;      // a ULS character at any baud (U19)
constexpr double request_bits = 10.0;     // the host's 8N1
constexpr std::size_t request_bytes = 5;  // "#aUS\r", "#aBM\r"

std::vector<std::uint8_t> unit_addresses(int count) {
  std::vector<std::uint8_t> addresses;
  const auto typable = rangekit::uls::typable_addresses();
  for (int i = 0; i < count && i < static_cast<int>(typable.size()); ++i) addresses.push_back(typable[i]);
  return addresses;
}

void BM_UlsBusPoll(benchmark::State& state) {
  const int units = static_cast<int>(state.range(0));
  const auto baud = static_cast<std::uint32_t>(state.range(1));
  const auto addresses = unit_addresses(units);
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores): the benchmark loop
    rangekit::bench::ScratchDir dir;
    const std::string bus_path = (dir.path() / "bus").string();
    const auto wire_log = dir.path() / "wire.log";
    std::vector<std::string> arguments{"uls", "--bus", bus_path, "--wire-log", wire_log.string()};
    for (const std::uint8_t address : addresses)
      arguments.insert(arguments.end(), {"--address", std::string(1, static_cast<char>(address))});
    auto sim = rangekit::bench::start_emulator(arguments, (dir.path() / "sim.log").string(), std::chrono::seconds(30));
    if (!sim) return state.SkipWithError(sim.error().message.c_str());
    auto link = rangekit::SerialPort::open(bus_path, rangekit::SerialSettings{115200});
    if (!link) return state.SkipWithError(link.error().message.c_str());
    rangekit::uls::Bus bus(std::move(*link));
    // Every unit at once, none answering (U4): stop, a reading every 2 ms, start; the baud below.
    bool set_up = bus.broadcast("ST") && bus.broadcast("AW", std::vector<std::string_view>{"8"}) &&
                  bus.broadcast("PO", std::vector<std::string_view>{"10", "10"}) &&
                  bus.broadcast("PF", std::vector<std::string_view>{"5000", "5000", "5000"});
    if (set_up && baud != 115200) {
      // Unit by unit, each answering at the old speed: after a broadcast BR no unit answered at
      // the new speed on this emulator (every 9600 row skipped).
      for (const std::uint8_t address : addresses) {
        set_up =
            set_up && bus.driver().set_address(address) && bus.driver().set_baud(rangekit::uls::BaudPort::output, baud);
      }
      auto slower = rangekit::SerialPort::open(bus_path, rangekit::SerialSettings{baud});
      set_up = set_up && slower && bus.driver().replace_transport(std::move(*slower)).ok();
      // A unit switches once its (unsent) $OK would have left the line: ask until one answers.
      bool answered = false;
      for (int attempt = 0; set_up && attempt < 20 && !answered; ++attempt) {
        answered = bus.poll({addresses.front()}, false).front().answered;
      }
      set_up = set_up && answered;
    }
    set_up = set_up && bus.broadcast("GO");
    // The first round reads each unit's MM/DM/MU/TB as well: not counted.
    for (const auto& unit : bus.poll(addresses, true)) set_up = set_up && unit.sample.has_value();
    if (!set_up) return state.SkipWithError("the bus could not be set up");

    const double round_s = static_cast<double>(units) * (2 * turnaround_s + 40.0 * 11.52 / baud);
    const int rounds = std::max(3, static_cast<int>(3.0 / round_s));  // about 3 s of polling
    const auto logged_before = std::filesystem::file_size(wire_log);
    int failed = 0;
    const auto started = Clock::now();
    for (int round = 0; round < rounds; ++round) {
      for (const auto& unit : bus.poll(addresses, true)) failed += unit.sample.has_value() ? 0 : 1;
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - started).count();
    sim->stop();  // flushes the wire log
    const auto reply_bytes = static_cast<double>(std::filesystem::file_size(wire_log) - logged_before);
    const double polls = static_cast<double>(rounds) * units;
    const double wire_s =
        (polls * 2 * request_bytes * request_bits + reply_bytes * reply_bits) / baud + polls * 2 * turnaround_s;
    state.counters["unit_polls_per_s"] = polls / seconds;
    state.counters["wire_polls_per_s"] = polls / wire_s;
    state.counters["efficiency"] = wire_s / seconds;
    state.counters["reply_bytes_per_poll"] = reply_bytes / polls;
    state.counters["failed"] = failed;
  }
}

}  // namespace

BENCHMARK(BM_UlsBusPoll)
    ->Args({16, 9600})
    ->Args({32, 9600})
    ->Args({16, 115200})
    ->Args({32, 115200})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();
