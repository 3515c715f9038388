// The latency timer of a USB serial adapter (FTDI's ftdi_sio: 16 ms by default), which
// `rangekit detect` reports: the adapter holds a short reply until the timer runs out, so
// every poll on the port costs at least one timer period.
#pragma once

#include <optional>
#include <string>

namespace rangekit::cli {

struct UsbLatency {
  std::string device;     // "ttyUSB0": the tty the port's path resolves to
  std::string attribute;  // the sysfs file that holds it, for `echo 1 > ...`
  int milliseconds = 0;
};

// The timer of the adapter behind `port` (a /dev/serial/by-id/ link is followed), read from
// SYSFS/bus/usb-serial/devices/<tty>/latency_timer; nothing for a port without one (CDC-ACM,
// CP210x, an on-board UART, a pty). SYSFS is $RANGEKIT_SYSFS_ROOT when set (the tests lay a
// folder out like sysfs), else /sys.
std::optional<UsbLatency> usb_latency(const std::string& port);

// What the timer costs a polled port and how to lower it: a line for the user; empty when
// the timer is already 1 ms or less.
std::string latency_advice(const UsbLatency& latency);

}  // namespace rangekit::cli
