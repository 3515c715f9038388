// Hosts emulated devices on pseudo-terminals: hands what the host writes to every device
// on that line (an RS-485 bus), runs their firmware on a real, scaled or virtual clock,
// and writes what their UARTs send back at the right moments.
#pragma once

#include <poll.h>

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "rangekit/sim/clock.hpp"
#include "rangekit/sim/control_socket.hpp"
#include "rangekit/sim/device_model.hpp"
#include "rangekit/sim/pty.hpp"

namespace rangekit {

struct LineAttachment {
  DeviceModel* device = nullptr;  // not owned
  std::size_t port = 0;
};

struct LineConfig {
  std::string name;                         // "universal", "bus", ...
  std::optional<std::string> link_path;     // symlink to the pty slave
  std::vector<LineAttachment> attachments;  // devices on this line
};

struct RuntimeOptions {
  bool virtual_clock = false;  // time moves only on {"cmd":"advance"} or advance_to()
  double time_scale = 1.0;     // real clock only: > 1 runs the firmware faster
  std::optional<std::string> control_path;
  std::uint32_t seed = 1;  // noise and garbling are repeatable
  // Every byte each line sends to the host, before line noise (bench/noise_bench.py's
  // truth: what a clean line would have carried).
  std::optional<std::string> wire_log_path;
  // Real clock only: the loop wakes when the devices ask (DeviceModel::next_wake) to the
  // nanosecond (0), or at every deadline with its wait rounded up to a multiple of this
  // (1 ms lets records at 1 kHz and above leave in millisecond batches, L78; kept so
  // bench/emulator_pacing_bench.cpp compares both in one run).
  Nanos wait_resolution{0};
};

// Faults of a real line are modelled by the runtime, not the firmware: mismatched speed or
// stop bits garble both ways, two devices talking at once corrupt each other's bytes, and
// injected noise (control: {"cmd":"noise", ...}) flips bits and drops bytes.
struct LineNoise {
  double bit_error_rate = 0;  // probability of flipping each bit sent to the host
  double drop_rate = 0;       // probability of losing each byte sent to the host
  double duplicate_rate = 0;  // probability of sending a byte twice
};

// How long the real-clock loop sleeps when the next device deadline is `until_deadline`
// away (real time): exactly that, within [0, max_wait], rounded up to a multiple of
// `resolution` when that is positive (RuntimeOptions::wait_resolution).
[[nodiscard]] Nanos loop_wait(Nanos until_deadline, Nanos max_wait, Nanos resolution);

class EmulatorRuntime {
 public:
  static Result<std::unique_ptr<EmulatorRuntime>> create(std::vector<LineConfig> lines, const RuntimeOptions& options);
  ~EmulatorRuntime();
  EmulatorRuntime(const EmulatorRuntime&) = delete;
  EmulatorRuntime& operator=(const EmulatorRuntime&) = delete;

  // Serves until `stop` becomes true (signal handler) or {"cmd":"shutdown"}.
  Status run(const std::atomic<bool>& stop);
  // One pass: read input, run devices to now, write output, answer control requests.
  // Waits at most `max_wait` for something to happen.
  Status step(Nanos max_wait);
  // Virtual clock: runs every device deadline up to `when`, in order.
  Status advance_to(Nanos when);

  [[nodiscard]] Nanos now() const;
  [[nodiscard]] const std::string& line_path(std::size_t line) const;
  [[nodiscard]] std::size_t line_count() const noexcept { return lines_.size(); }
  void set_noise(std::size_t line, const LineNoise& noise);
  // Bytes thrown away because no host was reading (pty buffer full).
  [[nodiscard]] std::uint64_t dropped_output_bytes() const noexcept { return dropped_output_; }
  // Extra control commands of the program hosting the runtime ("device" lookup by
  // label etc.); tried before the built-in ones return "unknown command". `now` is
  // the runtime's clock when the request is served, so a device acts at that moment
  // rather than at the last time it ran. A null reply means "not mine".
  using ControlExtension = std::function<nlohmann::json(const nlohmann::json& request, Nanos now)>;
  void set_control_extension(ControlExtension extension) { extension_ = std::move(extension); }

 private:
  struct SourcedByte {
    LineByte byte;
    std::size_t source;  // attachment index
  };
  struct Line {
    LineConfig config;
    std::unique_ptr<PseudoTerminal> pty;
    LineNoise noise;
  };
  EmulatorRuntime(std::vector<Line> lines, const RuntimeOptions& options);

  Status read_input(Nanos now);
  void run_devices(Nanos now);
  Status flush_output(Nanos now);
  [[nodiscard]] Nanos next_deadline() const;
  // The real-clock loop's next wake: the devices' next_wake() (whole runs of bytes).
  [[nodiscard]] Nanos next_wake() const;
  // Whether the host's port (`host`: its settings, read once per line and step: one
  // tcgetattr, not one per byte) reads what the device sends; `sent` carries the speed
  // and stop bits a byte left with (none: the device's present settings).
  [[nodiscard]] static bool host_matches(const Result<SerialSettings>& host, const LineAttachment& attachment,
                                         const LineByte* sent = nullptr);
  std::uint8_t garble(std::uint8_t value);
  nlohmann::json handle_control(const nlohmann::json& request);

  std::vector<Line> lines_;
  RuntimeOptions options_;
  std::unique_ptr<VirtualClock> virtual_clock_;
  std::unique_ptr<ScaledSteadyClock> real_clock_;
  std::unique_ptr<ControlSocket> control_;
  ControlExtension extension_;
  std::mt19937 random_;
  std::uint64_t dropped_output_ = 0;
  struct FileCloser {
    void operator()(std::FILE* file) const noexcept { (void)std::fclose(file); }
  };
  std::unique_ptr<std::FILE, FileCloser> wire_log_;
  bool shutdown_requested_ = false;
  // Reused by every step, so the loop allocates nothing while it paces output.
  std::vector<pollfd> poll_fds_;
  std::vector<DeviceModel*> advanced_;
  std::vector<LineByte> taken_;
  std::vector<SourcedByte> merged_;
  std::vector<std::uint8_t> wire_;
};

}  // namespace rangekit
