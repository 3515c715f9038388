// The service's RS-485 bus session against the wire (docs/performance.md, "RS-485 polling"):
// `rangekit serve` with a site of one bus of N emulated ULS units, each measuring faster than
// one bus cycle (PPM 10 at PRF 5000, set by broadcast before the service starts), first polled
// alone, then with two HTTP clients each asking its unit for every setting (`read`) and a
// single measurement in turn. The wire's minimum for the same polls comes from the emulator's
// wire log (the replies' bytes at 11.52 bits a character, U19; the requests at 10 bits; the
// 1 ms turnaround before each reply, U133); the command response times are set against the
// poll cycle, the time the service takes to poll every unit once. `uls bus poll` of the same bus
// (uls::Bus polling in turn) runs first, in the same run, beside the service's figure.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "host_stream_rig.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/uls/bus.hpp"
#include "service_rig.hpp"
#include "web/http_client.hpp"

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using ls5_driver_test::Child;
using rangekit::bench::percentile;

constexpr double turnaround_s = 0.001;    // the emulator's default (U133)
constexpr double reply_bits = 11.52;      // a ULS character at any baud (U19)
constexpr double request_bits = 10.0;     // the host's 8N1
constexpr std::size_t request_bytes = 5;  // "#aUS\r", "#aBM\r"
constexpr int clients = 2;

std::vector<std::uint8_t> unit_addresses(int count) {
  std::vector<std::uint8_t> addresses;
  const auto typable = rangekit::uls::typable_addresses();
  for (int i = 0; i < count && i < static_cast<int>(typable.size()); ++i) addresses.push_back(typable[i]);
  return addresses;
}

std::string unit_name(std::uint8_t address) { return std::string("unit-") + static_cast<char>(address); }

// Every unit at once, none answering (U4): stopped, Continuous Output off (§7), a reading every
// 2 ms, the line's baud, measuring. The bus at that baud, or what failed.
rangekit::Result<std::unique_ptr<rangekit::uls::Bus>> set_up_bus(const std::string& bus_path,
                                                                 const std::vector<std::uint8_t>& addresses,
                                                                 std::uint32_t baud) {
  using rangekit::Errc;
  auto link = rangekit::SerialPort::open(bus_path, rangekit::SerialSettings{115200});
  if (!link) return std::move(link).error();
  auto bus = std::make_unique<rangekit::uls::Bus>(std::move(*link));
  const std::string baud_text = std::to_string(baud);
  const bool set_up = bus->broadcast("ST") && bus->broadcast("CO", std::vector<std::string_view>{"0"}) &&
                      bus->broadcast("AW", std::vector<std::string_view>{"8"}) &&
                      bus->broadcast("PO", std::vector<std::string_view>{"10", "10"}) &&
                      bus->broadcast("PF", std::vector<std::string_view>{"5000", "5000", "5000"});
  if (!set_up) return rangekit::make_error(Errc::io, "ST, CO, AW, PO, PF not broadcast");
  if (baud != 115200) {
    // Unit by unit, each answering at the old speed: a broadcast BR left every unit silent at
    // the new one on this emulator (the bus bench's own set-up fails the same way).
    for (const std::uint8_t address : addresses) {
      (void)bus->driver().set_address(address);
      if (auto sent = bus->driver().set_baud(rangekit::uls::BaudPort::output, baud); !sent) return sent.error();
    }
    auto slower = rangekit::SerialPort::open(bus_path, rangekit::SerialSettings{baud});
    if (!slower) return std::move(slower).error();
    if (auto replaced = bus->driver().replace_transport(std::move(*slower)); !replaced) return replaced.error();
    // A unit switches once its (unsent) $OK would have left the line: ask until one answers.
    bool answered = false;
    for (int attempt = 0; attempt < 40 && !answered; ++attempt) {
      answered = bus->poll({addresses.front()}, false).front().answered;
    }
    if (!answered) return rangekit::make_error(Errc::timeout, "no unit answers at " + baud_text + " baud");
  }
  if (auto started = bus->broadcast("GO"); !started) return started.error();
  // The first round reads each unit's MM/DM/MU/TB as well.
  for (const auto& unit : bus->poll(addresses, true)) {
    if (!unit.sample) return rangekit::make_error(Errc::timeout, "unit " + unit_name(unit.address) + ": no BM");
  }
  return bus;
}

// `uls bus poll` of the same bus, same run: uls::Bus polling every unit in turn (US and BM)
// for `window`; unit polls a second, or nothing when one failed.
double library_polls_per_s(rangekit::uls::Bus& bus, const std::vector<std::uint8_t>& addresses,
                           std::chrono::seconds window) {
  double polls = 0;
  const auto started = Clock::now();
  while (Clock::now() - started < window) {
    for (const auto& unit : bus.poll(addresses, true)) {
      if (!unit.sample) return 0;
      polls += 1;
    }
  }
  return polls / std::chrono::duration<double>(Clock::now() - started).count();
}

// The samples of every sensor so far (GET /api/sensors, health.records).
double records_of(std::uint16_t port) {
  const auto reply = web_test::http(port, "GET", "/api/sensors");
  const auto json = nlohmann::json::parse(reply.body, nullptr, false);
  if (!json.is_object() || !json.contains("sensors")) return -1;
  double records = 0;
  for (const auto& sensor : json["sensors"]) records += sensor["health"]["records"].get<double>();
  return records;
}

bool every_unit_has_records(std::uint16_t port) {
  const auto json = nlohmann::json::parse(web_test::http(port, "GET", "/api/sensors").body, nullptr, false);
  if (!json.is_object() || !json.contains("sensors")) return false;
  return std::all_of(json["sensors"].begin(), json["sensors"].end(),
                     [](const auto& sensor) { return sensor["health"]["records"].template get<double>() > 0; });
}

// What the units sent in a window, from the wire log: polls (BM replies) and bytes.
struct WireWindow {
  double polls = 0;
  double reply_bytes = 0;
};
WireWindow wire_between(const std::filesystem::path& log, std::uintmax_t from, std::uintmax_t to) {
  std::ifstream file(log, std::ios::binary);
  file.seekg(static_cast<std::streamoff>(from));
  std::string bytes(to - from, '\0');
  file.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  WireWindow window;
  window.reply_bytes = static_cast<double>(file.gcount());
  for (auto at = bytes.find("BM,"); at != std::string::npos; at = bytes.find("BM,", at + 3)) window.polls += 1;
  return window;
}

// The wire's time for `polls` unit polls (US and BM) whose replies took `reply_bytes`.
double wire_seconds(double polls, double reply_bytes, double baud) {
  return (polls * 2 * request_bytes * request_bits + reply_bytes * reply_bits) / baud + polls * 2 * turnaround_s;
}

// Response times of `count` clients over `window`, client k at the k-th unit, each asking
// for every setting (`read`: some thirty requests) and a single measurement in turn.
struct Commands {
  std::vector<double> read_ms;
  std::vector<double> single_ms;
  double failed = 0;
};
Commands command_window(std::uint16_t port, const std::vector<std::uint8_t>& addresses, int count,
                        std::chrono::seconds window) {
  std::atomic<bool> stop{false};
  std::vector<Commands> each(static_cast<std::size_t>(count));
  std::vector<std::thread> threads;
  for (int client = 0; client < count; ++client) {
    threads.emplace_back([&, client] {
      Commands& mine = each[static_cast<std::size_t>(client)];
      const std::string base = "/api/sensors/" + unit_name(addresses[static_cast<std::size_t>(client)]) + "/actions/";
      for (int turn = 0; !stop; ++turn) {
        const bool read = turn % 2 == 0;
        const auto asked = Clock::now();
        const auto reply = web_test::http(port, "POST", base + (read ? "read" : "single"));
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - asked).count();
        if (reply.status != 200) mine.failed += 1;
        (read ? mine.read_ms : mine.single_ms).push_back(ms);
      }
    });
  }
  std::this_thread::sleep_for(window);  // the bench's window, not synchronisation
  stop = true;
  for (auto& thread : threads) thread.join();
  Commands all;
  for (const Commands& one : each) {
    all.read_ms.insert(all.read_ms.end(), one.read_ms.begin(), one.read_ms.end());
    all.single_ms.insert(all.single_ms.end(), one.single_ms.begin(), one.single_ms.end());
    all.failed += one.failed;
  }
  return all;
}

void BM_UlsBusService(benchmark::State& state) {
  const int units = static_cast<int>(state.range(0));
  const auto baud = static_cast<std::uint32_t>(state.range(1));
  const auto addresses = unit_addresses(units);
  // About 20 bus cycles in each window (a cycle: 1.4 s for 32 units at 9600, 0.17 s at 115200).
  const auto window = baud < 115200 ? 12s : 4s;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores): the benchmark loop
    rangekit::bench::ScratchDir dir;
    const std::string bus_path = (dir.path() / "bus").string();
    const auto wire_log = dir.path() / "wire.log";
    std::vector<std::string> arguments{"uls", "--bus", bus_path, "--wire-log", wire_log.string()};
    for (const std::uint8_t address : addresses)
      arguments.insert(arguments.end(), {"--address", std::string(1, static_cast<char>(address))});
    auto sim = rangekit::bench::start_emulator(arguments, (dir.path() / "sim.log").string(), 30s);
    if (!sim) return state.SkipWithError(sim.error().message.c_str());
    double library_rate = 0;
    {
      auto bus = set_up_bus(bus_path, addresses, baud);
      if (!bus) return state.SkipWithError(bus.error().describe().c_str());
      library_rate = library_polls_per_s(**bus, addresses, window / 2);
    }  // the port closed: the service's from here on
    std::string site;
    for (const std::uint8_t address : addresses) {
      site += "[[sensor]]\nname = \"" + unit_name(address) + "\"\nfamily = \"uls\"\nport = \"" + bus_path +
              "\"\nbaud = " + std::to_string(baud) + "\naddress = \"" + std::string(1, static_cast<char>(address)) +
              "\"\n";
    }
    std::ofstream(dir.path() / "site.toml") << site;
    Child service({"serve", "--config", (dir.path() / "site.toml").string(), "--listen", "127.0.0.1:0"});
    const std::uint16_t port = rangekit::bench::api_port_of(service);
    if (port == 0) return state.SkipWithError("the service did not print its API line");
    std::thread drain([&service] {
      while (!service.read_line().empty()) {
      }
    });
    const auto stop_service = [&] {
      service.terminate();
      drain.join();
      service.wait();
    };
    // Connecting reads every unit's settings first (about 30 requests each): at 9600, many seconds.
    const auto deadline = Clock::now() + 180s;
    while (Clock::now() < deadline && !every_unit_has_records(port)) std::this_thread::sleep_for(200ms);
    if (!every_unit_has_records(port)) {
      stop_service();
      return state.SkipWithError("not every unit was polled within 180 s");
    }

    // The poll alone: the wire log and the records over one window.
    auto log_before = std::filesystem::file_size(wire_log);
    double records_before = records_of(port);
    auto started = Clock::now();
    std::this_thread::sleep_for(window);  // the bench's window, not synchronisation
    auto log_after = std::filesystem::file_size(wire_log);
    const double records_after = records_of(port);
    double seconds = std::chrono::duration<double>(Clock::now() - started).count();
    const WireWindow alone_poll = wire_between(wire_log, log_before, log_after);
    const double wire_s = wire_seconds(alone_poll.polls, alone_poll.reply_bytes, baud);
    const double cycle_ms = 1000.0 * seconds * units / std::max(alone_poll.polls, 1.0);

    // Commands while it polls: one client alone (what a command costs on the polled bus), then
    // two, each at its own unit, every setting and a single measurement in turn.
    const Commands alone = command_window(port, addresses, 1, window);
    log_before = std::filesystem::file_size(wire_log);
    started = Clock::now();
    const Commands both = command_window(port, addresses, clients, window);
    const double busy_seconds = std::chrono::duration<double>(Clock::now() - started).count();
    log_after = std::filesystem::file_size(wire_log);
    const WireWindow busy = wire_between(wire_log, log_before, log_after);
    stop_service();
    sim->stop();

    std::vector<double> all = both.read_ms;
    all.insert(all.end(), both.single_ms.begin(), both.single_ms.end());
    // How long a command waited for others (polls, the other client's command) beyond what it
    // takes alone on the polled bus: the worse of the two kinds.
    const double wait_p99 = std::max(percentile(both.read_ms, 99) - percentile(alone.read_ms, 50),
                                     percentile(both.single_ms, 99) - percentile(alone.single_ms, 50));
    state.counters["unit_polls_per_s"] = alone_poll.polls / seconds;
    state.counters["library_polls_per_s"] = library_rate;
    state.counters["records_per_s"] = (records_after - records_before) / seconds;
    state.counters["wire_polls_per_s"] = alone_poll.polls / wire_s;
    state.counters["efficiency"] = wire_s / seconds;
    state.counters["reply_bytes_per_poll"] = alone_poll.reply_bytes / std::max(alone_poll.polls, 1.0);
    state.counters["cycle_ms"] = cycle_ms;
    state.counters["busy_unit_polls_per_s"] = busy.polls / busy_seconds;
    state.counters["commands"] = static_cast<double>(all.size());
    state.counters["failed"] = alone.failed + both.failed;
    state.counters["cmd_p50_ms"] = percentile(all, 50);
    state.counters["cmd_p99_ms"] = percentile(all, 99);
    state.counters["cmd_max_ms"] = percentile(all, 100);
    state.counters["read_p99_ms"] = percentile(both.read_ms, 99);
    state.counters["single_p99_ms"] = percentile(both.single_ms, 99);
    state.counters["alone_read_p50_ms"] = percentile(alone.read_ms, 50);
    state.counters["alone_single_p50_ms"] = percentile(alone.single_ms, 50);
    state.counters["wait_p99_ms"] = wait_p99;
  }
}

}  // namespace

BENCHMARK(BM_UlsBusService)
    ->Args({16, 9600})
    ->Args({32, 9600})
    ->Args({16, 115200})
    ->Args({32, 115200})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();
