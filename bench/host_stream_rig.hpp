// Shared pieces of the host streaming benches: an emulator in its own process (so its CPU
// stays out of the host's figures) with its control socket, a byte-counting transport, and
// `cat` of a pty into a file as the floor.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <benchmark/benchmark.h>

#include "cli/sim_process.hpp"
#include "rangekit/core/result.hpp"
#include "rangekit/core/transport.hpp"
#include "rangekit/sim/control_socket.hpp"
#include "rangekit/uls/driver.hpp"

namespace rangekit::bench {

// A scratch directory under the system's temp directory, removed when destroyed.
class ScratchDir {
 public:
  ScratchDir();
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const noexcept { return path_; }

 private:
  std::filesystem::path path_;
};

// One request on the emulator's control socket; the reply's JSON.
Result<nlohmann::json> control(const std::string& socket_path, const nlohmann::json& request);

// Forwards to another transport and counts the bytes read through it.
class CountingTransport final : public Transport {
 public:
  CountingTransport(TransportPtr inner, std::shared_ptr<std::atomic<std::uint64_t>> bytes)
      : inner_(std::move(inner)), bytes_(std::move(bytes)) {}
  Status write_all(Bytes data) override { return inner_->write_all(data); }
  Result<std::size_t> read_some(std::span<std::uint8_t> out, std::chrono::milliseconds timeout) override;
  void close() noexcept override { inner_->close(); }
  [[nodiscard]] std::string name() const override { return inner_->name(); }

 private:
  TransportPtr inner_;
  std::shared_ptr<std::atomic<std::uint64_t>> bytes_;
};

// CPU seconds (user + system) of this process, all threads.
double process_cpu_s();

// `cat` reading a terminal into a file: the floor a raw byte copy sets. The
// terminal gets VMIN 1 first (a raw port with VMIN 0 returns 0 bytes at once,
// which cat takes for the end of its input), as `stty min 1` would.
class CatCopy {
 public:
  static Result<std::unique_ptr<CatCopy>> start(const std::string& tty_path, const std::filesystem::path& out);
  ~CatCopy();
  CatCopy(const CatCopy&) = delete;
  CatCopy& operator=(const CatCopy&) = delete;
  // Writes to the same terminal (the commands that start and stop the stream).
  Status send(std::string_view text);
  [[nodiscard]] std::uintmax_t file_bytes() const;
  // Stops cat once its file ends with `ending` (the device's answer to the
  // request that stopped the stream: everything before it has been copied) or
  // after `limit`; returns cat's own CPU seconds (wait4 rusage).
  double finish(std::string_view ending, std::chrono::milliseconds limit);

 private:
  CatCopy(pid_t pid, int fd, std::filesystem::path out);
  pid_t pid_ = -1;
  int fd_ = -1;
  std::filesystem::path out_;
};

std::string read_file(const std::filesystem::path& path);

// One window of `cat` on `link` (the floor of the host streaming benches): sets `baud` raw on
// the pty's shared termios (as the host's stty would), starts cat into `out`, writes `start`,
// calls `mark` with cat's file size after `settle` and again `window` after that (the bench's
// own clock, not synchronisation), writes `stop` and ends cat once its file ends with `stopped`.
struct CatWindow {
  double stream_s = 0;  // from `start` to `stop`
  double cpu_s = 0;     // cat's own (wait4)
  std::string copied;   // what cat wrote
};
Result<CatWindow> cat_window(const std::string& link, const std::filesystem::path& out, std::uint32_t baud,
                             std::string_view start, std::string_view stop, std::string_view stopped,
                             std::chrono::milliseconds settle, std::chrono::milliseconds window,
                             const std::function<Status(std::uintmax_t file_bytes)>& mark);

// One run of a host (the driver or cat) on the emulator's pty: fills the figures, or
// returns what stopped it (empty when it ran).
using HostFigures = std::map<std::string, double>;
using HostRun = std::function<std::string(HostFigures&)>;

// The driver and cat in turn, `pairs` times, on the same emulator: a run's CPU moves by
// up to 2x on this VM (where its threads land), so one pair can flip a 1.5x goal either
// way. Counters: the pair with the median CPU ratio (driver/cat) as drv_* and cat_*,
// cpu_ratio (that median), cpu_ratio_low and _high, and over every driver run the
// records lost (lost_all) and the most allocations per record (allocs_per_record_max).
void run_paired(benchmark::State& state, const HostRun& driver, const HostRun& cat, int pairs = 3);

// `rangekit sim <arguments...>` from the CLI this bench was built with.
Result<cli::SimProcess> start_emulator(const std::vector<std::string>& arguments, const std::string& log_path,
                                       std::chrono::milliseconds timeout);
// An LS5 emulator on `port` (serial number `serial`) set to a result every 1 ms and every result
// sent (§8.4: T = n x t, t = 1 ms, n = 1): 1000 records a second.
Result<cli::SimProcess> start_ls5_at_1khz(const std::string& port, int serial, const std::string& log_path);
// A `sim uls --bus` on `port` with a unit at each address, Continuous Output turned off at each
// (§7: units talk on a bus only when addressed), then `configure` run with the driver addressed
// to each unit (false: the unit could not be set up).
Result<cli::SimProcess> start_uls_bus(const std::string& port, const std::vector<std::uint8_t>& addresses,
                                      const std::string& log_path,
                                      const std::function<bool(uls::Driver&)>& configure = {});

}  // namespace rangekit::bench
