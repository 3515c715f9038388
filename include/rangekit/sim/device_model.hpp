// What an emulator's firmware model offers the runtime that hosts it: a pure
// state machine fed with received bytes and time, giving back the bytes its
// UARTs put on the line, each with the moment its last bit left. The runtime
// (pty, sockets, real or virtual clock) wraps around it; tests drive it directly.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rangekit/core/serial_port.hpp"
#include "rangekit/sim/clock.hpp"

namespace rangekit {

// One byte on a serial line: `done` is when its stop bit ended.
struct LineByte {
  Nanos done{0};
  std::uint8_t value = 0;
  // The speed and stop bits it was sent with; 0 means the port's present ones. A
  // byte that left before a change (the $OK to BR, U36; the LS5's echo of a W to
  // 04/05, L28) must still be read with the old ones.
  std::uint32_t baud = 0;
  std::uint8_t stop_bits = 0;
};

class DeviceModel {
 public:
  DeviceModel() = default;
  DeviceModel(const DeviceModel&) = delete;
  DeviceModel& operator=(const DeviceModel&) = delete;
  virtual ~DeviceModel() = default;

  // Serial ports of the device (ULS: configuration and universal; LS5: one).
  [[nodiscard]] virtual std::size_t port_count() const noexcept = 0;
  // What the port's UART is set to now; a host using other settings sees garbage.
  [[nodiscard]] virtual SerialSettings port_settings(std::size_t port) const = 0;
  // A byte arrived whole on `port` at `now`.
  virtual void receive(std::size_t port, std::uint8_t byte, Nanos now) = 0;
  // Runs the firmware up to `now` (measurement cycles, timeouts).
  virtual void advance(Nanos now) = 0;
  // When advance() next has something to do (Nanos::max() when nothing is scheduled).
  [[nodiscard]] virtual Nanos next_deadline() const = 0;
  // When the real-clock loop must next run the device: at the latest next_deadline(),
  // but a model may name a later moment when nothing a host can see happens before it
  // (bytes leaving back to back are handed over when the run of them ends, as a host
  // acts on whole frames), saving the loop a wake per byte. advance() still runs every
  // event at its own time.
  [[nodiscard]] virtual Nanos next_wake() const { return next_deadline(); }
  // Appends the bytes of `port` whose last bit has left the line by `now`.
  virtual void take_line_output(std::size_t port, Nanos now, std::vector<LineByte>& out) = 0;
  // A control-socket request addressed to this device; returns the reply object.
  // Unknown requests answer {"error": "..."} naming the request.
  virtual nlohmann::json control(const nlohmann::json& request, Nanos now) = 0;
  // Short name for logs and control replies ("ULS #Z", "LS5 01").
  [[nodiscard]] virtual std::string label() const = 0;
};

}  // namespace rangekit
