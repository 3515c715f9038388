// A whole site on one service (docs/performance.md, "A site on one box"; `make bench-scale`):
// N LS5 heard over UDP at 1 kHz each (bench/rig/udp_pacer.cpp), 8 LS5 on serial lines at
// 1 kHz and two RS-485 buses of 16 ULS (the emulators), every sample captured, ten SSE
// clients at max_rate=30, MQTT at max_rate_hz=10 and the Modbus face on. For each N: the
// service's CPU and RSS, the latency from a packet leaving the rig to its SSE event, samples
// lost and capture rows a second. The baseline, in the same run: one `rangekit ls5 udp
// --format jsonl --capture FILE` process per UDP sensor, fed by the same rig.
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "build_paths.hpp"
#include "child_process.hpp"
#include "host_stream_rig.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/ls5/driver.hpp"
#include "rangekit/mqtt/local_broker.hpp"
#include "rangekit/uls/bus.hpp"
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
using rangekit::bench::status_mb;

constexpr int serial_ls5 = 8;
constexpr int buses = 2;
constexpr int units_per_bus = 16;
constexpr int sse_clients = 10;
constexpr auto settle = 5s;         // rings full (4096 items at 1 kHz)
constexpr auto client_settle = 3s;  // clients connected and caught up
constexpr auto window = 10s;
constexpr int first_udp_port = 41000;
constexpr int baseline_sensors = 64;
constexpr int records_per_packet = 168;
constexpr int packet_labels = 97;  // the pacer's codes: (packet % 97) x 168 + record

// A program of this build run with stdout and stderr to `log` (the pacer, a baseline process).
class Process {
 public:
  Process(const std::string& program, const std::vector<std::string>& arguments, const std::string& log) {
    pid_ = rangekit::test::fork_child();  // ends with the bench, even one that crashed
    if (pid_ == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
      ::dup2(fd, STDERR_FILENO);
      const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
      ::dup2(null, STDOUT_FILENO);
      std::vector<char*> argv{const_cast<char*>(program.c_str())};
      for (const auto& argument : arguments) argv.push_back(const_cast<char*>(argument.c_str()));
      argv.push_back(nullptr);
      ::execv(program.c_str(), argv.data());
      ::_exit(127);
    }
  }
  ~Process() { stop(); }
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;
  [[nodiscard]] pid_t pid() const { return pid_; }
  void stop() {
    if (pid_ <= 0 || waited_) return;
    rangekit::test::end_child(pid_);
    waited_ = true;
  }
  void wait() {
    if (pid_ <= 0 || waited_) return;
    int status = 0;
    ::waitpid(pid_, &status, 0);
    waited_ = true;
  }

 private:
  pid_t pid_ = -1;
  bool waited_ = false;
};

std::string pacer_path() {
  std::string cli = rangekit::test::cli_path();
  return cli.substr(0, cli.rfind('/') + 1) + "rangekit_udp_pacer";
}

// Send times of the pacer's packets, by sensor and packet label, from its log.
struct PacerLog {
  struct Packet {
    std::uint32_t number = 0;
    Clock::time_point sent;
  };
  std::map<int, std::vector<Packet>> by_sensor;
  std::uint64_t packets = 0;
  static PacerLog read(const std::string& path) {
    PacerLog log;
    std::ifstream file(path);
    int sensor = 0;
    std::uint32_t number = 0;
    long long ns = 0;
    while (file >> sensor >> number >> ns) {
      log.by_sensor[sensor].push_back({number, Clock::time_point(std::chrono::nanoseconds(ns))});
      ++log.packets;
    }
    return log;
  }
  // The packet that held `code` for `sensor`: the latest one with its label sent before `at`.
  [[nodiscard]] const Packet* packet_of(int sensor, int code, Clock::time_point at) const {
    const auto found = by_sensor.find(sensor);
    if (found == by_sensor.end() || code < 0) return nullptr;
    const auto label = static_cast<std::uint32_t>(code / records_per_packet);
    const Packet* best = nullptr;
    for (const Packet& packet : found->second) {
      if (packet.sent > at) break;
      if (packet.number % packet_labels == label) best = &packet;
    }
    return best;
  }
};

// For each event of a UDP sensor: which one, and its code (a sample's `code`, a merge's `last`).
struct UdpCode {
  int sensor = 0;
  int code = 0;
};
using SseClient = rangekit::bench::SseReader<UdpCode>;

int number_after(std::string_view block, std::string_view key) {
  const auto at = block.find(key);
  if (at == std::string_view::npos) return -1;
  return std::atoi(std::string(block.substr(at + key.size(), 8)).c_str());
}

std::unique_ptr<SseClient> sse_client(std::uint16_t port, const std::string& target) {
  return std::make_unique<SseClient>(port, target, [](std::string_view block) -> std::optional<UdpCode> {
    const int sensor = number_after(block, "\"sensor\":\"udp-");
    if (sensor < 0) return std::nullopt;
    const bool sample = block.find("event: sample") != std::string_view::npos;
    return UdpCode{sensor, number_after(block, sample ? "\"code\":" : "\"last\":")};
  });
}

// Per client and packet, from the packet's send to the first event that shows it. A packet's
// last reading comes later on its own: the spike check holds it until the next reading judges
// it, the sensor's next packet or 100 ms (docs/reliability.md).
std::vector<double> latencies_ms(const PacerLog& log, const std::vector<std::vector<SseClient::Arrival>>& clients,
                                 Clock::time_point from, Clock::time_point to) {
  std::vector<double> out;
  for (const auto& arrivals : clients) {
    std::set<std::pair<int, std::uint32_t>> seen;
    for (const auto& arrival : arrivals) {
      const PacerLog::Packet* packet = log.packet_of(arrival.what.sensor, arrival.what.code, arrival.at);
      if (packet == nullptr || packet->sent < from || packet->sent > to) continue;
      if (!seen.emplace(arrival.what.sensor, packet->number).second) continue;
      out.push_back(std::chrono::duration<double, std::milli>(arrival.at - packet->sent).count());
    }
  }
  return out;
}

// The emulators every N shares: the serial LS5 at 1 kHz and the two buses.
struct SerialSite {
  rangekit::bench::ScratchDir dir;
  std::vector<rangekit::cli::SimProcess> emulators;
  std::vector<std::string> ls5_ports;
  std::vector<std::string> bus_ports;
  std::string error;
  SerialSite();
  [[nodiscard]] double cpu() const {
    double total = 0;
    for (const auto& emulator : emulators) total += cpu_seconds(emulator.pid());
    return total;
  }
};

SerialSite::SerialSite() {
  for (int i = 0; i < serial_ls5; ++i) {
    const std::string port = (dir.path() / ("ls5-" + std::to_string(i))).string();
    auto started = rangekit::bench::start_ls5_at_1khz(port, 200 + i, (dir.path() / "emulators.log").string());
    if (!started) {
      error = started.error().describe();
      return;
    }
    emulators.push_back(std::move(started).value());
    ls5_ports.push_back(port);
  }
  const auto typable = rangekit::uls::typable_addresses();
  const std::vector<std::uint8_t> addresses(typable.begin(), typable.begin() + units_per_bus);
  for (int bus = 0; bus < buses; ++bus) {
    const std::string port = (dir.path() / ("bus-" + std::to_string(bus))).string();
    // The units' default 10 Hz output.
    auto started = rangekit::bench::start_uls_bus(port, addresses, (dir.path() / "emulators.log").string());
    if (!started) {
      error = started.error().describe();
      return;
    }
    emulators.push_back(std::move(started).value());
    bus_ports.push_back(port);
  }
}

// The whole site, or (same_work) the UDP sensors alone with their capture: the work the
// baseline's processes do, for the cost per sample against them.
std::string site_text(const SerialSite& site, int udp_sensors, bool same_work, std::uint16_t broker_port,
                      const std::string& captures) {
  std::ostringstream text;
  text << "[service]\ncapture_dir = \"" << captures << "\"\nmax_captures = 1024\n";
  if (!same_work) {
    text << "[mqtt]\nbroker = \"mqtt://127.0.0.1:" << broker_port << "\"\nmax_rate_hz = 10\n";
    text << "[modbus]\nlisten = \"127.0.0.1:0\"\n";
  }
  for (int i = 0; i < udp_sensors; ++i) {
    text << "[[sensor]]\nname = \"udp-" << i << "\"\nfamily = \"ls5\"\nudp = \"127.0.0.1:" << first_udp_port + i
         << "\"\ncapture = true\n";
  }
  if (same_work) return text.str();
  for (std::size_t i = 0; i < site.ls5_ports.size(); ++i) {
    text << "[[sensor]]\nname = \"line-" << i << "\"\nfamily = \"ls5\"\nport = \"" << site.ls5_ports[i]
         << "\"\ncapture = true\n";
  }
  const auto addresses = rangekit::uls::typable_addresses();
  for (std::size_t bus = 0; bus < site.bus_ports.size(); ++bus) {
    for (int unit = 0; unit < units_per_bus; ++unit) {
      text << "[[sensor]]\nname = \"bus" << bus << "-" << unit << "\"\nfamily = \"uls\"\nport = \""
           << site.bus_ports[bus] << "\"\naddress = " << static_cast<int>(addresses[unit]) << "\ncapture = true\n";
    }
  }
  return text.str();
}

struct Health {
  int connected = 0;
  double udp_records = 0;
  double all_records = 0;
  double lost = 0;
};

Health health_of(std::uint16_t port) {
  Health health;
  const auto response = web_test::http(port, "GET", "/api/sensors");
  const auto json = nlohmann::json::parse(response.body, nullptr, false);
  if (!json.is_object() || !json.contains("sensors")) return health;
  for (const auto& sensor : json["sensors"]) {
    const auto& figures = sensor["health"];
    health.connected += figures.value("connected", false) ? 1 : 0;
    const double records = figures.value("records", 0.0);
    health.all_records += records;
    if (sensor.value("name", "").rfind("udp-", 0) == 0) health.udp_records += records;
    health.lost += figures.value("lost", 0.0);
  }
  return health;
}

// Rows of the service's captures, the UDP sensors' and all.
std::pair<double, double> capture_rows(const std::filesystem::path& dir) {
  double udp = 0;
  double all = 0;
  if (!std::filesystem::exists(dir)) return {0, 0};
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".sqlite") continue;
    sqlite3* db = nullptr;
    if (sqlite3_open_v2(entry.path().c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
      sqlite3_stmt* statement = nullptr;
      const char* sql = "SELECT count(*), sum(source LIKE 'udp-%') FROM samples";
      if (sqlite3_prepare_v2(db, sql, -1, &statement, nullptr) == SQLITE_OK && sqlite3_step(statement) == SQLITE_ROW) {
        all += sqlite3_column_double(statement, 0);
        udp += sqlite3_column_double(statement, 1);
      }
      sqlite3_finalize(statement);
    }
    sqlite3_close(db);
  }
  return {udp, all};
}

void BM_SiteScale(benchmark::State& state) {
  const int udp_sensors = static_cast<int>(state.range(0));
  const bool same_work = state.range(1) != 0;
  if (rangekit::mqtt::LocalBroker::find_executable().empty()) {
    return state.SkipWithError("mosquitto is not installed (scripts/install-deps.sh)");
  }
  // Set up once for every N: eight LS5 to configure and 32 bus units take seconds.
  static const auto shared_site = std::make_unique<SerialSite>();
  const SerialSite& site = *shared_site;
  if (!site.error.empty()) return state.SkipWithError(site.error.c_str());
  rangekit::mqtt::LocalBrokerOptions broker_options;
  broker_options.dir = site.dir.path();
  auto broker = rangekit::mqtt::LocalBroker::start(broker_options);
  if (!broker) return state.SkipWithError(broker.error().describe().c_str());
  const auto window_s = std::chrono::duration<double>(window).count();
  const auto run_s = std::chrono::duration<double>(settle + client_settle + window + 2s).count();
  const int serial_sensors = same_work ? 0 : serial_ls5 + buses * units_per_bus;
  const int clients_count = same_work ? 0 : sse_clients;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores): the benchmark loop
    const std::string name = std::to_string(udp_sensors) + (same_work ? "-same" : "");
    const auto captures = site.dir.path() / ("captures-" + name);
    const auto site_file = site.dir.path() / "site.toml";
    std::ofstream(site_file) << site_text(site, udp_sensors, same_work, (*broker)->port(), captures.string());
    Child service({"serve", "--config", site_file.string(), "--listen", "127.0.0.1:0"});
    const std::uint16_t port = rangekit::bench::api_port_of(service);
    if (port == 0) return state.SkipWithError("the service did not print its API line");
    std::thread drain([&service] {
      while (!service.read_line().empty()) {
      }
    });
    // The serial sensors connect first; the UDP ones once their first packet comes.
    for (int i = 0; i < 200 && health_of(port).connected < serial_sensors; ++i) std::this_thread::sleep_for(50ms);
    const auto pacer_log = site.dir.path() / ("pacer-" + name + ".log");
    Process pacer(pacer_path(),
                  {"--first-port", std::to_string(first_udp_port), "--sensors", std::to_string(udp_sensors),
                   "--seconds", std::to_string(run_s), "--log", pacer_log.string()},
                  (site.dir.path() / "pacer.stderr").string());
    std::this_thread::sleep_for(settle);  // the rings full: what the clients add is theirs
    const double rss_before_clients = status_mb(service.pid(), "VmRSS:");
    std::vector<std::unique_ptr<SseClient>> clients;
    for (int i = 0; i < clients_count; ++i) {
      clients.push_back(sse_client(port, "/api/events?max_rate=30"));
    }
    std::unique_ptr<SseClient> probe;
    if (!same_work) probe = sse_client(port, "/api/sensors/udp-0/events");
    std::this_thread::sleep_for(client_settle);
    const auto from = Clock::now();
    const double cpu_before = cpu_seconds(service.pid());
    const double pacer_before = cpu_seconds(pacer.pid());
    const double emulators_before = site.cpu();
    const Health before = health_of(port);
    std::this_thread::sleep_for(window);
    const double service_cpu = cpu_seconds(service.pid()) - cpu_before;
    const double pacer_cpu = cpu_seconds(pacer.pid()) - pacer_before;
    const double emulators_cpu = site.cpu() - emulators_before;
    const Health after = health_of(port);
    const auto to = Clock::now();
    const double rss = status_mb(service.pid(), "VmRSS:");
    const double peak_rss = status_mb(service.pid(), "VmHWM:");
    std::uint64_t client_events = 0;
    for (const auto& client : clients) client_events += client->events();
    pacer.wait();                        // its last packets sent and its log written
    std::this_thread::sleep_for(300ms);  // the last packets reach the service and the clients
    const Health done = health_of(port);
    std::vector<std::vector<SseClient::Arrival>> aggregated;
    for (const auto& client : clients) aggregated.push_back(client->arrivals());
    std::vector<std::vector<SseClient::Arrival>> probed;
    if (probe) probed.push_back(probe->arrivals());
    clients.clear();
    probe.reset();
    service.terminate();
    drain.join();
    service.wait();

    const PacerLog log = PacerLog::read(pacer_log.string());
    const auto sample_latency = latencies_ms(log, probed, from, to);
    const auto aggregate_latency = latencies_ms(log, aggregated, from, to);
    const double sent = static_cast<double>(log.packets) * records_per_packet;
    const auto [udp_rows, all_rows] = capture_rows(captures);
    state.counters["sensors"] = udp_sensors + serial_sensors;
    state.counters["samples_per_s"] = (after.all_records - before.all_records) / window_s;
    state.counters["service_cpu_pct"] = 100.0 * service_cpu / window_s;
    state.counters["pacer_cpu_pct"] = 100.0 * pacer_cpu / window_s;
    state.counters["emulators_cpu_pct"] = same_work ? 0 : 100.0 * emulators_cpu / window_s;
    state.counters["rss_MB"] = rss;
    state.counters["peak_rss_MB"] = peak_rss;
    state.counters["rss_per_client_MB"] = clients_count > 0 ? (rss - rss_before_clients) / (clients_count + 1) : 0;
    state.counters["sse_ev_per_s"] =
        clients_count > 0 ? static_cast<double>(client_events) / window_s / clients_count : 0;
    state.counters["udp_sent"] = sent;
    state.counters["udp_lost"] = sent - done.udp_records;
    state.counters["lost_reported"] = done.lost;
    state.counters["udp_rows_lost"] = sent - udp_rows;
    state.counters["capture_rows"] = all_rows;
    state.counters["capture_rows_per_s"] = (after.all_records - before.all_records) / window_s;
    state.counters["lat_packets"] = static_cast<double>(sample_latency.size());
    state.counters["lat_p50_ms"] = percentile(sample_latency, 50);
    state.counters["lat_p99_ms"] = percentile(sample_latency, 99);
    state.counters["agg_lat_p50_ms"] = percentile(aggregate_latency, 50);
    state.counters["agg_lat_p99_ms"] = percentile(aggregate_latency, 99);
  }
}

// The baseline: one `rangekit ls5 udp --format jsonl --capture FILE` process per sensor.
void BM_SiteScaleSeparateProcesses(benchmark::State& state) {
  const int udp_sensors = static_cast<int>(state.range(0));
  rangekit::bench::ScratchDir dir;
  const auto window_s = std::chrono::duration<double>(window).count();
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores): the benchmark loop
    std::vector<std::unique_ptr<Process>> processes;
    for (int i = 0; i < udp_sensors; ++i) {
      processes.push_back(std::make_unique<Process>(
          rangekit::test::cli_path(),
          std::vector<std::string>{"ls5", "udp", "--udp-listen", "127.0.0.1:" + std::to_string(first_udp_port + i),
                                   "--format", "jsonl", "--capture",
                                   (dir.path() / ("udp-" + std::to_string(i) + ".sqlite")).string()},
          (dir.path() / "processes.log").string()));
    }
    std::this_thread::sleep_for(1s);  // the listeners bound before the first packet
    const auto pacer_log = dir.path() / "pacer.log";
    Process pacer(
        pacer_path(),
        {"--first-port", std::to_string(first_udp_port), "--sensors", std::to_string(udp_sensors), "--seconds",
         std::to_string(std::chrono::duration<double>(settle + window + 1s).count()), "--log", pacer_log.string()},
        (dir.path() / "pacer.stderr").string());
    std::this_thread::sleep_for(settle);
    double before = 0;
    for (const auto& process : processes) before += cpu_seconds(process->pid());
    std::this_thread::sleep_for(window);
    double cpu = 0;
    for (const auto& process : processes) cpu += cpu_seconds(process->pid());
    cpu -= before;
    pacer.wait();
    processes.clear();
    state.counters["sensors"] = udp_sensors;
    state.counters["samples_per_s"] = udp_sensors * 1000.0;
    state.counters["cpu_pct"] = 100.0 * cpu / window_s;
    state.counters["per_process_cpu_pct"] = 100.0 * cpu / window_s / udp_sensors;
  }
}

// Only for `make bench-scale` (minutes): RANGEKIT_BENCH_SCALE lists the N to run, the whole
// site for each, then the same work as the baseline at 64 and the baseline itself.
const bool registered = [] {
  const char* sizes = std::getenv("RANGEKIT_BENCH_SCALE");
  if (sizes == nullptr) return false;
  std::istringstream list(sizes);
  for (std::string size; std::getline(list, size, ',');) {
    benchmark::RegisterBenchmark("BM_SiteScale", BM_SiteScale)
        ->Args({std::stoi(size), 0})
        ->Iterations(1)
        ->Unit(benchmark::kSecond)
        ->UseRealTime();
  }
  benchmark::RegisterBenchmark("BM_SiteScale", BM_SiteScale)
      ->Args({baseline_sensors, 1})
      ->Iterations(1)
      ->Unit(benchmark::kSecond)
      ->UseRealTime();
  benchmark::RegisterBenchmark("BM_SiteScaleSeparateProcesses", BM_SiteScaleSeparateProcesses)
      ->Arg(baseline_sensors)
      ->Iterations(1)
      ->Unit(benchmark::kSecond)
      ->UseRealTime();
  return true;
}();

}  // namespace
