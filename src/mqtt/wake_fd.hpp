// The eventfd that wakes the bridge's network thread out of its poll(): hub items,
// command replies or a stop.
#pragma once

#include <sys/eventfd.h>
#include <unistd.h>

#include <cstdint>

namespace rangekit::mqtt {

// Shared with the hub's listener, which the hub may still be calling while the bridge
// stops: the fd closes when the last holder lets go, so a late wake-up never writes to a
// closed (or reused) descriptor.
struct WakeFd {
  int fd = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  WakeFd() = default;
  ~WakeFd() {
    if (fd >= 0) ::close(fd);
  }
  WakeFd(const WakeFd&) = delete;
  WakeFd& operator=(const WakeFd&) = delete;
  void signal() const {
    const std::uint64_t one = 1;
    if (::write(fd, &one, sizeof one) < 0) return;  // full counter: a wake-up is pending anyway
  }
};

}  // namespace rangekit::mqtt
