#include "cli/systemd_notify.hpp"

#include <sys/stat.h>
#include <systemd/sd-daemon.h>

#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string_view>

namespace rangekit::cli {
namespace {

// A lost notification is nothing the service can mend: systemd notices a missing
// READY=1 (start timeout) or WATCHDOG=1 (restart) by itself.
void notify(const std::string& state) { (void)::sd_notify(0, state.c_str()); }

}  // namespace

SystemdNotify::SystemdNotify() {
  std::uint64_t usec = 0;
  if (::sd_watchdog_enabled(0, &usec) > 0 && usec > 0) interval_ = std::chrono::microseconds(usec);
}

void SystemdNotify::ready(const std::string& status) {
  notify("READY=1\nSTATUS=" + status);
  next_ping_ = std::chrono::steady_clock::now() + interval_ / 2;
}

void SystemdNotify::keep_alive(const std::function<std::string()>& probe) {
  if (interval_.count() == 0 || std::chrono::steady_clock::now() < next_ping_) return;
  const std::string status = probe();
  notify("WATCHDOG=1\nSTATUS=" + status);
  next_ping_ = std::chrono::steady_clock::now() + interval_ / 2;
}

void SystemdNotify::stopping() { notify("STOPPING=1\nSTATUS=stopping: ending every stream"); }

bool writes_to_journal(std::FILE* stream) {
  const char* named = std::getenv("JOURNAL_STREAM");  // NOLINT(concurrency-mt-unsafe): nothing sets it
  if (named == nullptr) return false;
  const std::string_view text(named);
  const auto colon = text.find(':');
  if (colon == std::string_view::npos) return false;
  std::uint64_t device = 0;
  std::uint64_t inode = 0;
  const auto device_end = text.data() + colon;
  if (std::from_chars(text.data(), device_end, device).ptr != device_end) return false;
  if (std::from_chars(device_end + 1, text.data() + text.size(), inode).ptr != text.data() + text.size()) return false;
  struct stat info {};
  if (::fstat(::fileno(stream), &info) != 0) return false;
  return info.st_dev == device && info.st_ino == inode;
}

std::string state_path(const std::string& path, const std::string& site_file) {
  const std::filesystem::path given(path);
  if (given.is_absolute()) return path;
  // NOLINTNEXTLINE(concurrency-mt-unsafe): nothing sets it
  if (const char* state = std::getenv("STATE_DIRECTORY"); state != nullptr && *state != '\0') {
    const std::string_view list(state);
    return (std::filesystem::path(list.substr(0, list.find(':'))) / given).string();
  }
  if (site_file.empty()) return path;
  return (std::filesystem::path(site_file).parent_path() / given).string();
}

}  // namespace rangekit::cli
