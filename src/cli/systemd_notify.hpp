// `rangekit serve` as a systemd service (docs/deploy.md): the notify protocol of a
// Type=notify unit, the journal as stdout, and the state folder systemd hands over.
#pragma once

#include <chrono>
#include <cstdio>
#include <functional>
#include <string>

namespace rangekit::cli {

// sd_notify(3) to $NOTIFY_SOCKET; without it (not under systemd) every call does nothing.
class SystemdNotify {
 public:
  // Reads the watchdog's interval from WATCHDOG_USEC (sd_watchdog_enabled).
  SystemdNotify();
  // READY=1, with a STATUS= line for `systemctl status`.
  void ready(const std::string& status);
  // Once half the watchdog interval has passed since the last ping: runs `probe` and sends
  // WATCHDOG=1 with its STATUS= after it returned, so a hub that stops answering stops the
  // pings and systemd restarts the service. Cheap to call often: not due, it does nothing.
  void keep_alive(const std::function<std::string()>& probe);
  // STOPPING=1: systemctl shows the service stopping while it ends its streams.
  void stopping();
  [[nodiscard]] std::chrono::microseconds watchdog_interval() const { return interval_; }

 private:
  std::chrono::microseconds interval_{0};  // 0: no watchdog asked for
  std::chrono::steady_clock::time_point next_ping_{};
};

// Whether `stream` writes to the journal: JOURNAL_STREAM names the device and inode of the
// stream systemd connected, so a stdout the unit redirected elsewhere is not taken for it.
bool writes_to_journal(std::FILE* stream);

// Where a file the service writes goes (captures, the token): an absolute path as given; a
// relative one in $STATE_DIRECTORY (the first, when systemd gives several) when systemd set
// it, since /etc is read only there; else beside the site file (as given when there is none).
std::string state_path(const std::string& path, const std::string& site_file);

}  // namespace rangekit::cli
