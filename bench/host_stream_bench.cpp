// Host streaming at the LS5's fastest rate (issue 6): 1000 records/s at 921600
// baud from a paced device on a pty, read (a) by the LS5 driver's stream and
// (b) by `cat` into a file, the floor. Reports records delivered against sent
// (goal >= 95 %, none lost) and CPU per second of streaming (goal < 5 % of a core).
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <string>
#include <thread>

#include "rangekit/core/pty.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/ls5/driver.hpp"

namespace {

using namespace std::chrono_literals;
constexpr int records_per_second = 1000;  // §8.4: t = 1 ms, n = 1
constexpr auto stream_time = 5s;

double thread_cpu_s() {
  timespec now{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + static_cast<double>(now.tv_nsec) / 1e9;
}

double process_cpu_s(int who) {
  rusage usage{};
  ::getrusage(who, &usage);
  auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) / 1e6; };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// The sensor side: answers ID (§9.2 example) and, after ST, writes one `!ddddd`
// record per millisecond on absolute deadlines for stream_time.
struct PacedLs5 {
  std::unique_ptr<rangekit::PseudoTerminal> pty;
  std::atomic<std::uint64_t> sent{0};
  double cpu_s = 0;

  // Opens the pty and the host's end of it, raw 921600 8N1 as the driver sets it.
  rangekit::Result<std::unique_ptr<rangekit::SerialPort>> open_host_side() {
    auto opened = rangekit::PseudoTerminal::open();
    if (!opened) return std::move(opened).error();
    pty = std::move(opened).value();
    return rangekit::SerialPort::open(pty->slave_path(), rangekit::SerialSettings{921600});
  }

  void serve(bool wait_for_start) {
    const double cpu_start = thread_cpu_s();
    const int fd = pty->native_handle();
    std::string input;
    while (wait_for_start) {
      pollfd descriptor{fd, POLLIN, 0};
      if (::poll(&descriptor, 1, 5000) <= 0) return;
      char buffer[256];
      const ssize_t got = ::read(fd, buffer, sizeof buffer);
      if (got <= 0) return;
      input.append(buffer, static_cast<std::size_t>(got));
      if (input.find("#01ID\r") != std::string::npos) {
        const std::string id = "%01LS5.6.0   b8,1234d40,0010s/n0000157\r";
        (void)!::write(fd, id.data(), id.size());
        input.clear();
      }
      if (input.find("#01ST\r") != std::string::npos) break;
    }
    const auto start = std::chrono::steady_clock::now();
    const auto end = start + stream_time;
    std::uint64_t index = 0;
    for (auto due = start; due < end; due += 1ms) {
      std::this_thread::sleep_until(due);  // the device's own clock, not test synchronisation
      char record[8];
      std::snprintf(record, sizeof record, "!%05u\r", static_cast<unsigned>(20000 + index % 10000));
      if (::write(fd, record, 7) != 7) break;
      ++index;
    }
    sent = index;
    cpu_s = thread_cpu_s() - cpu_start;
  }
};

void BM_HostLs5StreamAt1kHz921600(benchmark::State& state) {
  for (auto _ : state) {
    PacedLs5 device;
    auto port = device.open_host_side();
    if (!port) return state.SkipWithError(port.error().describe().c_str());
    std::thread sensor([&] { device.serve(true); });
    const double cpu_before = process_cpu_s(RUSAGE_SELF);
    rangekit::ls5::Driver driver(std::move(port).value(), rangekit::ls5::DriverOptions{});
    auto stream = driver.start_stream({});
    if (!stream) {
      sensor.join();
      return state.SkipWithError(stream.error().describe().c_str());
    }
    std::uint64_t received = 0;
    const auto give_up = std::chrono::steady_clock::now() + stream_time + 3s;
    while (std::chrono::steady_clock::now() < give_up) {
      auto item = (*stream)->next(200ms);
      if (item && std::holds_alternative<rangekit::Sample>(*item)) ++received;
      if (!item && device.sent > 0 && received >= device.sent) break;
    }
    sensor.join();
    const double host_cpu = process_cpu_s(RUSAGE_SELF) - cpu_before - device.cpu_s;
    const double seconds = std::chrono::duration<double>(stream_time).count();
    state.counters["sent"] = static_cast<double>(device.sent.load());
    state.counters["received"] = static_cast<double>(received);
    state.counters["delivered_pct"] = 100.0 * static_cast<double>(received) / static_cast<double>(device.sent.load());
    state.counters["host_cpu_pct"] = 100.0 * host_cpu / seconds;
    state.counters["lost"] = static_cast<double>((*stream)->lost());
  }
}

// The floor: `cat` of the same pty into a file, same records, same pacing.
void BM_CatFloorAt1kHz921600(benchmark::State& state) {
  for (auto _ : state) {
    PacedLs5 device;
    auto port = device.open_host_side();
    if (!port) return state.SkipWithError(port.error().describe().c_str());
    const auto out = std::filesystem::temp_directory_path() / ("rangekit-cat-" + std::to_string(::getpid()));
    const double children_before = process_cpu_s(RUSAGE_CHILDREN);
    const pid_t cat = ::fork();
    if (cat == 0) {
      const int in = ::open(device.pty->slave_path().c_str(), O_RDONLY | O_NOCTTY);
      const int file = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      // The port is raw with VMIN 0 (reads return at once); cat takes 0 bytes for
      // the end of its input, so it waits for one byte at least, as `stty min 1` would.
      termios settings{};
      ::tcgetattr(in, &settings);
      settings.c_cc[VMIN] = 1;
      settings.c_cc[VTIME] = 0;
      ::tcsetattr(in, TCSANOW, &settings);
      ::dup2(in, STDIN_FILENO);
      ::dup2(file, STDOUT_FILENO);
      ::execlp("cat", "cat", static_cast<char*>(nullptr));
      ::_exit(127);
    }
    device.serve(false);
    // Let cat drain what is in the pty, then stop it.
    const auto expected = device.sent.load() * 7;
    const auto give_up = std::chrono::steady_clock::now() + 3s;
    while (std::chrono::steady_clock::now() < give_up && std::filesystem::file_size(out) < expected) {
      ::poll(nullptr, 0, 10);
    }
    ::kill(cat, SIGTERM);
    ::waitpid(cat, nullptr, 0);
    const double cat_cpu = process_cpu_s(RUSAGE_CHILDREN) - children_before;
    const auto bytes = std::filesystem::file_size(out);
    std::filesystem::remove(out);
    const double seconds = std::chrono::duration<double>(stream_time).count();
    state.counters["sent"] = static_cast<double>(device.sent.load());
    state.counters["received"] = static_cast<double>(bytes / 7);
    state.counters["delivered_pct"] = 100.0 * static_cast<double>(bytes) / static_cast<double>(expected);
    state.counters["host_cpu_pct"] = 100.0 * cat_cpu / seconds;
  }
}

}  // namespace

BENCHMARK(BM_HostLs5StreamAt1kHz921600)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK(BM_CatFloorAt1kHz921600)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
