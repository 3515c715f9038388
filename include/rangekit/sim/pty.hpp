// A pseudo-terminal pair: the emulators hold the master end and publish the
// slave's path (optionally as a symlink, like `socat ... link=PATH`) so that any
// serial program can open it as if it were a real port.
#pragma once

#include <sys/stat.h>

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

  // Whether a symlink left at `link_path` by a killed emulator points at nothing of
  // its own any more: its pty is gone, or the kernel gave that /dev/pts number to a
  // newer pty (one created after the link). Not stale: no symlink there, or a link to
  // anything else (a live emulator's pty, a file the user put there).
  static bool link_is_stale(const std::string& link_path);

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

// The decision of link_is_stale on the two stat results, apart for tests: a target
// that is a character device changed (created) after the link was made is a reused pty.
bool pty_target_is_newer_than_link(const struct stat& link, const struct stat& target);

}  // namespace rangekit
