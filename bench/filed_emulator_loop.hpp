// The CPU baseline of bench/emulator_pacing_bench.cpp: the emulator's real-clock loop of
// 63b405f for one device on one pty, costs included (whole-millisecond poll(), a read() per
// wake, a tcgetattr() per byte). Kept unchanged on purpose: the present loop may cost no more.
#pragma once

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <set>
#include <vector>

#include "rangekit/sim/clock.hpp"
#include "rangekit/sim/device_model.hpp"
#include "rangekit/sim/pty.hpp"

namespace rangekit::bench {

class FiledEmulatorLoop {
 public:
  FiledEmulatorLoop(PseudoTerminal& pty, DeviceModel& device) : pty_(pty), device_(device) {}

  [[nodiscard]] Nanos now() const { return clock_.now(); }

  void run(const std::atomic<bool>& stop) {
    while (!stop.load()) step(std::chrono::milliseconds(50));
  }

 private:
  struct SourcedByte {
    LineByte byte;
    std::size_t source;
  };

  void step(Nanos max_wait) {
    std::vector<pollfd> fds;
    fds.push_back(pollfd{pty_.native_handle(), POLLIN, 0});
    Nanos wait = max_wait;
    const Nanos deadline = device_.next_deadline();
    if (deadline != Nanos::max()) wait = std::clamp(clock_.real_duration(deadline - now()), Nanos(0), max_wait);
    const int timeout_ms = static_cast<int>((wait.count() + 999'999) / 1'000'000);
    if (::poll(fds.data(), fds.size(), timeout_ms) < 0 && errno != EINTR) return;
    const Nanos current = now();
    read_input(current);
    std::set<DeviceModel*> done;
    if (done.insert(&device_).second) device_.advance(current);
    flush_output(current);
  }

  bool host_matches(const LineByte* sent) const {
    const auto host = pty_.peer_settings();
    if (!host) return true;
    SerialSettings device = device_.port_settings(0);
    if (sent != nullptr && sent->baud != 0) device.baud = sent->baud;
    if (sent != nullptr && sent->stop_bits != 0) device.stop_bits = sent->stop_bits;
    return host->baud == device.baud && host->stop_bits == device.stop_bits;
  }

  void read_input(Nanos current) {
    std::uint8_t buffer[512];
    while (true) {
      const ssize_t n = ::read(pty_.native_handle(), buffer, sizeof buffer);
      if (n <= 0) {
        if (n < 0 && errno == EINTR) continue;
        break;
      }
      const bool matches = host_matches(nullptr);
      for (ssize_t i = 0; i < n; ++i) device_.receive(0, matches ? buffer[i] : buffer[i] ^ 0x55U, current);
    }
  }

  void flush_output(Nanos current) {
    std::vector<LineByte> taken;
    std::vector<SourcedByte> merged;
    device_.take_line_output(0, current, taken);
    for (const auto& byte : taken) merged.push_back(SourcedByte{byte, 0});
    if (merged.empty()) return;
    std::stable_sort(merged.begin(), merged.end(),
                     [](const SourcedByte& a, const SourcedByte& b) { return a.byte.done < b.byte.done; });
    std::vector<std::uint8_t> wire;
    wire.reserve(merged.size());
    for (const auto& sourced : merged) {
      const SerialSettings settings = device_.port_settings(sourced.source);
      character_time_ = Nanos(static_cast<std::int64_t>(settings.bits_per_byte()) * 1'000'000'000LL / settings.baud);
      std::uint8_t value = sourced.byte.value;
      if (!host_matches(&sourced.byte)) value ^= 0x55U;
      wire.push_back(value);
    }
    std::size_t written = 0;
    while (written < wire.size()) {
      const ssize_t n = ::write(pty_.native_handle(), wire.data() + written, wire.size() - written);
      if (n > 0) {
        written += static_cast<std::size_t>(n);
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      break;
    }
  }

  PseudoTerminal& pty_;
  DeviceModel& device_;
  ScaledSteadyClock clock_;
  Nanos character_time_{0};  // the half-duplex collision span the loop computed per byte
};

}  // namespace rangekit::bench
