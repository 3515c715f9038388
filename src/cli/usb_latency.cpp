#include "cli/usb_latency.hpp"

#include <fmt/core.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace rangekit::cli {

std::optional<UsbLatency> usb_latency(const std::string& port) {
  std::error_code error;
  const std::filesystem::path device = std::filesystem::canonical(port, error);
  if (error) return std::nullopt;
  const char* root = std::getenv("RANGEKIT_SYSFS_ROOT");  // NOLINT(concurrency-mt-unsafe): nothing sets it
  const std::filesystem::path sysfs = root != nullptr && *root != '\0' ? root : "/sys";
  UsbLatency latency;
  latency.device = device.filename().string();
  latency.attribute = "/sys/bus/usb-serial/devices/" + latency.device + "/latency_timer";
  std::ifstream file(sysfs / "bus/usb-serial/devices" / latency.device / "latency_timer");
  if (!(file >> latency.milliseconds) || latency.milliseconds < 0) return std::nullopt;
  return latency;
}

std::string latency_advice(const UsbLatency& latency) {
  if (latency.milliseconds <= 1) return {};
  return fmt::format(
      "{0}: its USB serial adapter holds each short reply until its {1} ms latency timer runs out, so every poll "
      "on this port costs at least {1} ms: at most {2} polls a second, shared by every unit of an RS-485 bus. "
      "Set 1 ms now with `echo 1 > {3}` (as root), or at every plug-in with the udev rule "
      "/lib/udev/rules.d/99-rangekit-ftdi-latency.rules copied to /etc/udev/rules.d/ and uncommented "
      "(docs/deploy.md)",
      latency.device, latency.milliseconds, 1000 / latency.milliseconds, latency.attribute);
}

}  // namespace rangekit::cli
