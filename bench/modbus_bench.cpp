// The Modbus face under load (docs/modbus.md): `rangekit serve --demo` asked by 10 (and 32)
// libmodbus clients, each polling a unit's 17 first input registers every 10 ms on absolute
// deadlines (1000 requests/s from 10), against the same demo without the face, same run: the
// service's CPU both ways and each request's response time.
#include <benchmark/benchmark.h>
#include <modbus.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "ls5_driver/cli_process.hpp"
#include "service_rig.hpp"

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using ls5_driver_test::Child;
using rangekit::bench::cpu_seconds;
using rangekit::bench::percentile;

constexpr auto settle = 2s;  // the demo's sensors connect and stream
constexpr auto window = 10s;
constexpr auto poll_period = 10ms;

// Starts the demo (with the face when `modbus`) and reads its output until it serves; the
// face's port, 0 without it or when it did not start.
struct Demo {
  std::unique_ptr<Child> service;
  std::uint16_t modbus_port = 0;
  bool up = false;
  std::thread drain;
  explicit Demo(bool modbus) {
    std::vector<std::string> arguments{"serve", "--demo", "--listen", "127.0.0.1:0"};
    if (modbus) arguments.insert(arguments.end(), {"--modbus", "127.0.0.1:0"});
    service = std::make_unique<Child>(arguments);
    static const std::regex modbus_line(R"(Modbus TCP on 127\.0\.0\.1:(\d+))");
    for (std::string line = service->read_line(); !line.empty(); line = service->read_line()) {
      std::smatch found;
      if (std::regex_search(line, found, modbus_line)) modbus_port = static_cast<std::uint16_t>(std::stoi(found[1]));
      if (line.find("API on http://127.0.0.1:") != std::string::npos) {
        up = true;
        break;
      }
    }
    drain = std::thread([this] {
      while (!service->read_line().empty()) {
      }
    });
  }
  ~Demo() {
    service->terminate();
    drain.join();
    service->wait();
  }
  Demo(const Demo&) = delete;
  Demo& operator=(const Demo&) = delete;
};

// CPU seconds of the service over the window, while `load` runs beside it.
template <class Load>
double service_cpu(pid_t pid, Load&& load) {
  std::this_thread::sleep_for(settle);
  const double before = cpu_seconds(pid);
  load();
  return cpu_seconds(pid) - before;
}

void BM_ModbusClientsAt100Hz(benchmark::State& state) {
  const auto clients = static_cast<int>(state.range(0));
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores): the benchmark loop
    double baseline_cpu = 0;
    {
      Demo demo(false);
      if (!demo.up) return state.SkipWithError("the demo without the face did not start");
      baseline_cpu = service_cpu(demo.service->pid(), [] { std::this_thread::sleep_for(window); });
    }
    Demo demo(true);
    if (!demo.up || demo.modbus_port == 0) return state.SkipWithError("the demo with the face did not start");
    std::mutex mutex;
    std::vector<double> response_ms;
    std::atomic<int> failed{0};
    const double cpu = service_cpu(demo.service->pid(), [&] {
      std::vector<std::thread> threads;
      const auto start = Clock::now();
      for (int client = 0; client < clients; ++client) {
        threads.emplace_back([&, client] {
          modbus_t* context = modbus_new_tcp("127.0.0.1", demo.modbus_port);
          if (context == nullptr || modbus_connect(context) != 0) {
            ++failed;
            if (context != nullptr) modbus_free(context);
            return;
          }
          modbus_set_slave(context, 1 + client % 7);
          std::vector<double> mine;
          std::array<std::uint16_t, 17> registers{};
          // Each client starts a tenth of a period after the one before, as independent PLCs would.
          auto next = start + client * poll_period / clients;
          while (next < start + window) {
            std::this_thread::sleep_until(next);
            const auto asked = Clock::now();
            if (modbus_read_input_registers(context, 0, 17, registers.data()) != 17) ++failed;
            mine.push_back(std::chrono::duration<double, std::milli>(Clock::now() - asked).count());
            next += poll_period;
          }
          modbus_close(context);
          modbus_free(context);
          const std::lock_guard lock(mutex);
          response_ms.insert(response_ms.end(), mine.begin(), mine.end());
        });
      }
      for (auto& thread : threads) thread.join();
    });
    const double seconds = std::chrono::duration<double>(window).count();
    state.counters["baseline_cpu_pct"] = 100.0 * baseline_cpu / seconds;
    state.counters["service_cpu_pct"] = 100.0 * cpu / seconds;
    state.counters["cpu_ratio"] = baseline_cpu > 0 ? cpu / baseline_cpu : 0;
    state.counters["added_cpu_us_per_request"] =
        response_ms.empty() ? 0 : 1e6 * (cpu - baseline_cpu) / static_cast<double>(response_ms.size());
    state.counters["requests"] = static_cast<double>(response_ms.size());
    state.counters["failed"] = failed.load();
    state.counters["resp_p50_ms"] = percentile(response_ms, 50);
    state.counters["resp_p99_ms"] = percentile(response_ms, 99);
    state.counters["resp_max_ms"] = percentile(response_ms, 100);
  }
}

}  // namespace

// 10 clients for the goals; 32, the most the face is asked to serve at once at this rate.
BENCHMARK(BM_ModbusClientsAt100Hz)->Arg(10)->Arg(32)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
