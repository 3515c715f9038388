// The sensor service under load (docs/service.md): two 1 kHz LS5 and a 10 Hz bus of four
// ULS served to ten SSE clients, against `rangekit ls5 stream` of the same LS5 in the same
// run; CPU, RSS and record-to-SSE latency (records relayed through a pty, matched by code).
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "host_stream_rig.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/ls5/driver.hpp"
#include "rangekit/uls/driver.hpp"
#include "service_rig.hpp"
#include "sse_reader.hpp"
#include "web/http_client.hpp"

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using ls5_driver_test::Child;
using rangekit::bench::cpu_seconds;
using rangekit::bench::percentile;
using rangekit::bench::Relay;
using rangekit::bench::status_mb;

constexpr auto settle = 2s;  // from the start of the streams to the window's start
constexpr auto window = 5s;
constexpr int sse_clients = 10;

// A client of /api/events that notes the code of each sample of `sensor`.
using SseClient = rangekit::bench::SseReader<int>;

std::unique_ptr<SseClient> sse_client(std::uint16_t port, const std::string& sensor) {
  const std::string marker = "\"sensor\":\"" + sensor + "\"";
  return std::make_unique<SseClient>(port, "/api/events", [marker](std::string_view block) -> std::optional<int> {
    const auto code_at = block.find("\"code\":");
    if (block.find(marker) == std::string_view::npos || code_at == std::string_view::npos) return std::nullopt;
    return std::atoi(std::string(block.substr(code_at + 7, 6)).c_str());
  });
}

// Latencies in ms: each arrival matched with the next record of the same code the
// relay wrote (records the service never delivered are skipped over).
std::vector<double> latencies_ms(const std::vector<Relay::Record>& records, const std::vector<SseClient::Arrival>& got,
                                 Clock::time_point from, Clock::time_point to) {
  std::vector<double> out;
  std::size_t next = 0;
  for (const auto& arrival : got) {
    std::size_t at = next;
    while (at < records.size() && records[at].code != arrival.what) ++at;
    if (at == records.size()) continue;  // not one the relay saw (before it started)
    next = at + 1;
    if (records[at].written < from || records[at].written > to) continue;
    out.push_back(std::chrono::duration<double, std::milli>(arrival.at - records[at].written).count());
  }
  return out;
}

struct Site {
  rangekit::bench::ScratchDir dir;
  std::vector<rangekit::cli::SimProcess> emulators;
  std::vector<std::string> ls5_ports;
  std::string bus;
  std::string error;
  Site();
};

Site::Site() {
  for (int i = 0; i < 2; ++i) {
    const std::string port = (dir.path() / ("ls5-" + std::to_string(i))).string();
    auto started = rangekit::bench::start_ls5_at_1khz(port, 100 + i,
                                                      (dir.path() / ("ls5-" + std::to_string(i) + ".log")).string());
    if (!started) {
      error = started.error().describe();
      return;
    }
    emulators.push_back(std::move(started).value());
    ls5_ports.push_back(port);
  }
  bus = (dir.path() / "bus").string();
  // AW below PPM (§3 "must be less then the PPM"): §9's 3000/300 Hz, 10 Hz.
  auto started = rangekit::bench::start_uls_bus(
      bus, {'A', 'B', 'C', 'D'}, (dir.path() / "bus.log").string(), [](rangekit::uls::Driver& driver) {
        return driver.set_averaging_weight(256) && driver.set_pulses_per_measurement(300, 1024) && driver.set_prf(3000);
      });
  if (!started) {
    error = started.error().describe();
    return;
  }
  emulators.push_back(std::move(started).value());
}

void BM_ServiceVersusLs5Stream(benchmark::State& state) {
  Site site;
  if (!site.error.empty()) return state.SkipWithError(site.error.c_str());
  const auto window_s = std::chrono::duration<double>(window).count();
  for (auto _ : state) {
    // Baseline: `rangekit ls5 stream` of each LS5, its own process.
    double baseline_cpu = 0;
    {
      std::vector<std::unique_ptr<Child>> streams;
      for (const auto& port : site.ls5_ports) {
        streams.push_back(std::make_unique<Child>(std::vector<std::string>{"ls5", "stream", "--port", port, "--format",
                                                                           "jsonl", "--out", "/dev/null", "--quiet"}));
      }
      std::this_thread::sleep_for(settle);  // the bench's window, not synchronisation
      std::vector<double> before;
      for (const auto& stream : streams) before.push_back(cpu_seconds(stream->pid()));
      std::this_thread::sleep_for(window);
      for (std::size_t i = 0; i < streams.size(); ++i) baseline_cpu += cpu_seconds(streams[i]->pid()) - before[i];
      for (const auto& stream : streams) stream->terminate();
      for (const auto& stream : streams) stream->wait();
    }

    // The service: the first LS5 through the relay, the second direct, the bus.
    std::string error;
    auto relay = Relay::start(site.ls5_ports[0], error);
    if (!relay) return state.SkipWithError(error.c_str());
    std::string text = "[[sensor]]\nname = \"belt-1\"\nfamily = \"ls5\"\nport = \"" + relay->path() +
                       "\"\n[[sensor]]\nname = \"belt-2\"\nfamily = \"ls5\"\nport = \"" + site.ls5_ports[1] + "\"\n";
    for (const char* unit : {"A", "B", "C", "D"}) {
      text += std::string("[[sensor]]\nname = \"bay-") + unit + "\"\nfamily = \"uls\"\nport = \"" + site.bus +
              "\"\naddress = \"" + unit + "\"\n";
    }
    const auto site_file = site.dir.path() / "site.toml";
    std::ofstream(site_file) << text;
    Child service({"serve", "--config", site_file.string(), "--listen", "127.0.0.1:0"});
    const std::uint16_t port = rangekit::bench::api_port_of(service);
    if (port == 0) return state.SkipWithError("the service did not print its API line");
    std::thread drain([&service] {
      while (!service.read_line().empty()) {
      }
    });
    // First without clients (the hub and the idle server), then with the ten.
    std::this_thread::sleep_for(settle);  // the bench's window, not synchronisation
    const double idle_before = cpu_seconds(service.pid());
    std::this_thread::sleep_for(window);
    const double service_idle_cpu = cpu_seconds(service.pid()) - idle_before;
    std::vector<std::unique_ptr<SseClient>> clients;
    for (int i = 0; i < sse_clients; ++i) clients.push_back(sse_client(port, "belt-1"));
    std::this_thread::sleep_for(settle);
    const auto from = Clock::now();
    const double cpu_before = cpu_seconds(service.pid());
    std::vector<std::uint64_t> events_before;
    for (const auto& client : clients) events_before.push_back(client->events());
    std::this_thread::sleep_for(window);
    const double service_cpu = cpu_seconds(service.pid()) - cpu_before;
    const auto to = Clock::now();
    double events = 0;
    for (std::size_t i = 0; i < clients.size(); ++i) {
      events += static_cast<double>(clients[i]->events() - events_before[i]);
    }
    const double rss = status_mb(service.pid(), "VmRSS:");
    const double peak_rss = status_mb(service.pid(), "VmHWM:");
    const auto sensors = web_test::http(port, "GET", "/api/sensors");
    const auto json = nlohmann::json::parse(sensors.body, nullptr, false);
    std::this_thread::sleep_for(200ms);  // the last events of the window reach the clients
    std::vector<double> latencies;
    const auto records = relay->records();
    for (const auto& client : clients) {
      const auto more = latencies_ms(records, client->arrivals(), from, to);
      latencies.insert(latencies.end(), more.begin(), more.end());
    }
    clients.clear();
    service.terminate();
    drain.join();
    service.wait();
    relay.reset();

    state.counters["window_s"] = window_s;
    state.counters["baseline_cpu_pct"] = 100.0 * baseline_cpu / window_s;
    state.counters["service_cpu_pct"] = 100.0 * service_cpu / window_s;
    state.counters["no_client_cpu_pct"] = 100.0 * service_idle_cpu / window_s;
    state.counters["cpu_ratio"] = baseline_cpu > 0 ? service_cpu / baseline_cpu : 0;
    state.counters["rss_MB"] = rss;
    state.counters["peak_rss_MB"] = peak_rss;
    state.counters["sse_ev_per_s"] = events / window_s / sse_clients;  // per client
    state.counters["lat_samples"] = static_cast<double>(latencies.size());
    state.counters["lat_p50_ms"] = percentile(latencies, 50);
    state.counters["lat_p99_ms"] = percentile(latencies, 99);
    state.counters["lat_max_ms"] = percentile(latencies, 100);
    if (json.is_object()) {
      for (const auto& sensor : json["sensors"]) {
        const std::string name = sensor["name"];
        if (name == "belt-1" || name == "bay-A") state.counters[name + "_hz"] = sensor["health"]["rate_hz"];
      }
    }
  }
}

}  // namespace

BENCHMARK(BM_ServiceVersusLs5Stream)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
