// The MQTT bridge under load (docs/mqtt.md): `rangekit serve` publishing two 1 kHz LS5 at
// full rate against `rangekit ls5 stream | mosquitto_pub -l` in the same run; CPU, loss and
// record-to-subscriber latency (records relayed through a pty, matched by their code).
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <mosquitto.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include "build_paths.hpp"

#include <array>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "host_stream_rig.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/ls5/driver.hpp"
#include "rangekit/mqtt/local_broker.hpp"
#include "service_rig.hpp"

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using ls5_driver_test::Child;
using rangekit::bench::cpu_seconds;
using rangekit::bench::percentile;
using rangekit::bench::Relay;

constexpr auto settle = 2s;  // from the start of the streams to the window's start
constexpr auto window = 5s;
constexpr auto drain = 1s;  // after the window: its last messages reach the subscriber

// The target sweeps 10 -> 46 mm in 10 s and starts again: 3.6 µm a millisecond, about
// 4.5 codes of a 40 mm sensor (formula 8.5: code = distance / range x 50000).
constexpr const char* ramp_scene = "[target]\npath = [[0.0, 10.0], [10.0, 46.0]]\nrepeat = true\nnoise_mm = 0.0\n";

// A libmosquitto client in the bench: each reading message's code and arrival time, by topic.
class Subscriber {
 public:
  struct Arrival {
    int code = 0;
    Clock::time_point at;
  };
  explicit Subscriber(std::uint16_t port) {
    mosquitto_lib_init();
    client_ = mosquitto_new(("rangekit-bench-" + std::to_string(::getpid())).c_str(), true, this);
    mosquitto_connect_callback_set(client_, [](mosquitto* client, void* self, int rc) {
      if (rc != 0) return;
      mosquitto_subscribe(client, nullptr, "rangekit/+/reading", 0);
      mosquitto_subscribe(client, nullptr, "pipe/+/reading", 0);
      static_cast<Subscriber*>(self)->connected_ = true;
    });
    mosquitto_message_callback_set(client_, [](mosquitto*, void* self, const mosquitto_message* message) {
      const auto now = Clock::now();
      const std::string payload(static_cast<const char*>(message->payload),
                                static_cast<std::size_t>(message->payloadlen));
      const auto at = payload.find("\"code\":");
      if (at == std::string::npos) return;
      auto& subscriber = *static_cast<Subscriber*>(self);
      const std::lock_guard lock(subscriber.mutex_);
      subscriber.arrivals_[message->topic].push_back({std::atoi(payload.c_str() + at + 7), now});
    });
    mosquitto_connect_async(client_, "127.0.0.1", port, 30);
    mosquitto_loop_start(client_);
  }
  ~Subscriber() {
    mosquitto_disconnect(client_);
    mosquitto_loop_stop(client_, false);
    mosquitto_destroy(client_);
  }
  Subscriber(const Subscriber&) = delete;
  Subscriber& operator=(const Subscriber&) = delete;
  [[nodiscard]] bool connected() const { return connected_; }
  std::vector<Arrival> arrivals(const std::string& topic) {
    const std::lock_guard lock(mutex_);
    return arrivals_[topic];
  }

 private:
  mosquitto* client_ = nullptr;
  std::atomic<bool> connected_{false};
  std::mutex mutex_;
  std::map<std::string, std::vector<Arrival>> arrivals_;
};

// `rangekit ls5 stream --port PORT --format jsonl | mosquitto_pub -l -t TOPIC`: two processes.
class Pipeline {
 public:
  Pipeline(const std::string& port, std::uint16_t broker_port, const std::string& topic, const std::string& log) {
    std::array<int, 2> pipe{-1, -1};
    if (::pipe2(pipe.data(), O_CLOEXEC) != 0) return;
    std::vector<std::string> stream_args{
        rangekit::test::cli_path(), "ls5", "stream", "--port", port, "--format", "jsonl", "--quiet"};
    std::vector<std::string> publish_args{"mosquitto_pub", "-h", "127.0.0.1", "-p", std::to_string(broker_port), "-t",
                                          topic,           "-l"};
    stream_ = spawn(stream_args, -1, pipe[1], log);
    publisher_ = spawn(publish_args, pipe[0], -1, log);
    ::close(pipe[0]);
    ::close(pipe[1]);
  }
  ~Pipeline() {
    for (const pid_t pid : {stream_, publisher_}) {
      if (pid > 0) ::kill(pid, SIGTERM);
    }
    for (const pid_t pid : {stream_, publisher_}) {
      if (pid > 0) ::waitpid(pid, nullptr, 0);
    }
  }
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;
  [[nodiscard]] std::vector<pid_t> pids() const { return {stream_, publisher_}; }

 private:
  static pid_t spawn(std::vector<std::string>& args, int in, int out, const std::string& log) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    if (in >= 0) posix_spawn_file_actions_adddup2(&actions, in, STDIN_FILENO);
    if (out >= 0) posix_spawn_file_actions_adddup2(&actions, out, STDOUT_FILENO);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    std::vector<char*> argv;
    argv.reserve(args.size() + 1);
    for (auto& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    pid_t pid = -1;
    if (posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid = -1;
    posix_spawn_file_actions_destroy(&actions);
    return pid;
  }
  pid_t stream_ = -1;
  pid_t publisher_ = -1;
};

struct Figures {
  double cpu_s = 0;
  double broker_cpu_s = 0;
  std::vector<double> latencies;  // ms, records written in the window
  std::size_t records = 0;        // written in the window
  std::size_t delivered = 0;      // of those, arrived at the subscriber
};

// Each arrival matched with the next record of the same code the relay wrote since the
// phase began (records that never arrived are skipped over).
void match(const std::vector<Relay::Record>& all, const std::vector<Subscriber::Arrival>& got, Clock::time_point begin,
           Clock::time_point from, Clock::time_point to, Figures& figures) {
  std::vector<Relay::Record> records;
  for (const auto& record : all) {
    if (record.written < begin) continue;
    records.push_back(record);
    if (record.written >= from && record.written <= to) ++figures.records;
  }
  std::size_t next = 0;
  for (const auto& arrival : got) {
    std::size_t at = next;
    while (at < records.size() && records[at].code != arrival.code) ++at;
    if (at == records.size()) continue;  // not one the relay saw since the phase began
    next = at + 1;
    if (records[at].written < from || records[at].written > to) continue;
    ++figures.delivered;
    figures.latencies.push_back(std::chrono::duration<double, std::milli>(arrival.at - records[at].written).count());
  }
}

// The window: CPU of `pids` and the broker, then the records of each relay against the
// messages of its topic.
Figures measure(const std::vector<pid_t>& pids, pid_t broker, const std::vector<std::unique_ptr<Relay>>& relays,
                Subscriber& subscriber, const std::vector<std::string>& topics, Clock::time_point begin) {
  Figures figures;
  std::this_thread::sleep_for(settle);  // the bench's window, not synchronisation
  double before = 0;
  for (const pid_t pid : pids) before += cpu_seconds(pid);
  const double broker_before = cpu_seconds(broker);
  const auto from = Clock::now();
  std::this_thread::sleep_for(window);
  const auto to = Clock::now();
  for (const pid_t pid : pids) figures.cpu_s += cpu_seconds(pid);
  figures.cpu_s -= before;
  figures.broker_cpu_s = cpu_seconds(broker) - broker_before;
  std::this_thread::sleep_for(drain);
  for (std::size_t i = 0; i < relays.size(); ++i) {
    match(relays[i]->records(), subscriber.arrivals(topics[i]), begin, from, to, figures);
  }
  return figures;
}

void BM_MqttServiceVersusPipelines(benchmark::State& state) {
  if (rangekit::mqtt::LocalBroker::find_executable().empty()) {
    return state.SkipWithError("mosquitto is not installed (scripts/install-deps.sh)");
  }
  rangekit::bench::ScratchDir dir;
  const auto scene = dir.path() / "ramp.toml";
  std::ofstream(scene) << ramp_scene;
  std::vector<rangekit::cli::SimProcess> emulators;
  std::vector<std::unique_ptr<Relay>> relays;
  for (int i = 0; i < 2; ++i) {
    const std::string port = (dir.path() / ("ls5-" + std::to_string(i))).string();
    auto started = rangekit::bench::start_emulator(
        {"ls5", "--port", port, "--serial", std::to_string(100 + i), "--scene", scene.string()},
        (dir.path() / ("ls5-" + std::to_string(i) + ".log")).string(), 10s);
    if (!started) return state.SkipWithError(started.error().describe().c_str());
    emulators.push_back(std::move(started).value());
    {
      auto link = rangekit::SerialPort::open(port, rangekit::SerialSettings{115200});
      if (!link) return state.SkipWithError(link.error().describe().c_str());
      // §8.4: T = n x t; 1 ms and every result: 1000 records/s (7 bytes each fit 115200 8N1).
      rangekit::ls5::Driver driver(std::move(link).value(), rangekit::ls5::DriverOptions{});
      for (const auto& [name, value] : {std::pair{"period-ms", "1"}, std::pair{"thinning", "1"}}) {
        if (auto done = driver.set(name, value); !done) return state.SkipWithError(done.error().describe().c_str());
      }
    }
    std::string error;
    relays.push_back(Relay::start(port, error));
    if (!relays.back()) return state.SkipWithError(error.c_str());
  }
  rangekit::mqtt::LocalBrokerOptions broker_options;
  broker_options.dir = dir.path();
  auto broker = rangekit::mqtt::LocalBroker::start(broker_options);
  if (!broker) return state.SkipWithError(broker.error().describe().c_str());
  const std::uint16_t broker_port = (*broker)->port();
  const pid_t broker_pid = (*broker)->pid();
  Subscriber subscriber(broker_port);
  for (int i = 0; i < 200 && !subscriber.connected(); ++i) std::this_thread::sleep_for(50ms);
  if (!subscriber.connected()) return state.SkipWithError("the bench's subscriber did not connect");
  std::this_thread::sleep_for(200ms);  // its SUBSCRIBEs reach the broker

  const auto window_s = std::chrono::duration<double>(window).count();
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores): the benchmark loop
    // Baseline: one pipeline per LS5.
    Figures baseline;
    {
      const auto begin = Clock::now();
      std::vector<std::unique_ptr<Pipeline>> pipelines;
      std::vector<pid_t> pids;
      for (std::size_t i = 0; i < relays.size(); ++i) {
        pipelines.push_back(std::make_unique<Pipeline>(relays[i]->path(), broker_port,
                                                       "pipe/ls5-" + std::to_string(i) + "/reading",
                                                       (dir.path() / "pipelines.log").string()));
        for (const pid_t pid : pipelines.back()->pids()) pids.push_back(pid);
      }
      baseline = measure(pids, broker_pid, relays, subscriber, {"pipe/ls5-0/reading", "pipe/ls5-1/reading"}, begin);
    }

    // The service: both LS5, every sample published.
    const auto site_file = dir.path() / "site.toml";
    std::ofstream(site_file) << "[mqtt]\nbroker = \"mqtt://127.0.0.1:" << broker_port
                             << "\"\nmax_rate_hz = 0\n[[sensor]]\nname = \"belt-1\"\nfamily = \"ls5\"\nport = \""
                             << relays[0]->path() << "\"\n[[sensor]]\nname = \"belt-2\"\nfamily = \"ls5\"\nport = \""
                             << relays[1]->path() << "\"\n";
    const auto begin = Clock::now();
    Child service({"serve", "--config", site_file.string(), "--listen", "127.0.0.1:0"});
    bool up = false;
    for (std::string line = service.read_line(); !line.empty() && !up; line = service.read_line()) {
      up = line.find("API on http://127.0.0.1:") != std::string::npos;
    }
    if (!up) return state.SkipWithError("the service did not print its API line");
    std::thread drain_output([&service] {
      while (!service.read_line().empty()) {
      }
    });
    const Figures figures = measure({service.pid()}, broker_pid, relays, subscriber,
                                    {"rangekit/belt-1/reading", "rangekit/belt-2/reading"}, begin);
    const double rss = rangekit::bench::status_mb(service.pid(), "VmRSS:");
    service.terminate();
    drain_output.join();
    service.wait();

    state.counters["window_s"] = window_s;
    state.counters["baseline_cpu_pct"] = 100.0 * baseline.cpu_s / window_s;
    state.counters["service_cpu_pct"] = 100.0 * figures.cpu_s / window_s;
    state.counters["cpu_ratio"] = baseline.cpu_s > 0 ? figures.cpu_s / baseline.cpu_s : 0;
    state.counters["broker_cpu_pct_baseline"] = 100.0 * baseline.broker_cpu_s / window_s;
    state.counters["broker_cpu_pct_service"] = 100.0 * figures.broker_cpu_s / window_s;
    state.counters["rss_MB"] = rss;
    state.counters["records"] = static_cast<double>(figures.records);
    state.counters["lost"] = static_cast<double>(figures.records - figures.delivered);
    state.counters["lat_p50_ms"] = percentile(figures.latencies, 50);
    state.counters["lat_p99_ms"] = percentile(figures.latencies, 99);
    state.counters["lat_max_ms"] = percentile(figures.latencies, 100);
    state.counters["baseline_records"] = static_cast<double>(baseline.records);
    state.counters["baseline_lost"] = static_cast<double>(baseline.records - baseline.delivered);
    state.counters["baseline_lat_p50_ms"] = percentile(baseline.latencies, 50);
    state.counters["baseline_lat_p99_ms"] = percentile(baseline.latencies, 99);
  }
}

}  // namespace

BENCHMARK(BM_MqttServiceVersusPipelines)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
