// A pseudo-terminal pair: the emulators hold the master end and publish the
// slave's path (optionally as a symlink, like `socat ... link=PATH`) so that any
// serial program can open it as if it were a real port.
#pragma once

#include <optional>
#include <string>

#include "rangekit/core/fd_transport.hpp"
#include "rangekit/core/serial_port.hpp"

namespace rangekit {

class PseudoTerminal final : public FdTransport {
 public:
  // Opens a new pty in raw mode. With `link_path`, creates a symlink there to the
  // slave device; fails with a clear error if something already exists at that path.
  static Result<std::unique_ptr<PseudoTerminal>> open(std::optional<std::string> link_path = std::nullopt);
  ~PseudoTerminal() override;  // removes the symlink it created

  [[nodiscard]] const std::string& slave_path() const noexcept { return slave_path_; }
  // The path users open: the symlink when there is one, else the slave device.
  [[nodiscard]] const std::string& public_path() const noexcept { return link_path_ ? *link_path_ : slave_path_; }
  // Line settings the program on the slave side chose (shared termios).
  [[nodiscard]] Result<SerialSettings> peer_settings() const { return read_serial_settings(native_handle()); }
  // Keeps the slave open from this process too, so the master does not see
  // EIO while no client is connected. Off by default: EIO is how the emulator
  // notices a client going away.
  Status hold_slave_open();

 private:
  PseudoTerminal(int master_fd, std::string slave_path, std::optional<std::string> link_path);
  std::string slave_path_;
  std::optional<std::string> link_path_;
  int held_slave_fd_ = -1;
};

}  // namespace rangekit
