// Captures the service runs (§2 Start Capture / Stop Capture, for any number of
// sensors): each is a hub subscriber writing every sample and event of its
// sensors into an append-only SQLite capture (docs/capture.md) from a thread of
// its own. A capture keeps up or counts what it lost; it never slows a sensor.
// Downloads convert a capture to CSV, JSON lines or the Interface Program's .log.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/hub/hub.hpp"

namespace rangekit::hub {

struct CaptureInfo {
  std::string id;                    // "20261201-130405-1": also the file's name
  std::vector<std::string> sensors;  // empty: every sensor of the site
  std::string path;                  // the SQLite file
  std::chrono::system_clock::time_point started;
  std::optional<std::chrono::system_clock::time_point> stopped;
  bool active = false;
  std::uint64_t samples = 0;  // written
  std::uint64_t events = 0;
  std::uint64_t lost = 0;  // the capture fell behind (its queue overflowed)
  std::string error;       // why it stopped by itself (disk full, ...)
};

enum class DownloadFormat : std::uint8_t { sqlite, csv, jsonl, log };
Result<DownloadFormat> parse_download_format(std::string_view name);

// What one client may not exhaust: each running capture has a thread, three files open and
// a queue of up to a minute of readings, and each start leaves a file behind.
struct CaptureLimits {
  std::size_t running = 16;                                  // captures running at once
  std::uintmax_t min_free_bytes = std::uintmax_t{64} << 20;  // free space the folder's file system needs for a start
};

class CaptureManager {
 public:
  // Captures go into `directory` (made if missing).
  CaptureManager(Hub& hub, std::string directory, CaptureLimits limits = {});
  ~CaptureManager();  // stop_all()
  CaptureManager(const CaptureManager&) = delete;
  CaptureManager& operator=(const CaptureManager&) = delete;

  // Errc::limit when `limits.running` captures run already or the folder's file system has
  // less than `limits.min_free_bytes` free.
  Result<CaptureInfo> start(const std::vector<std::string>& sensors);
  Result<CaptureInfo> stop(const std::string& id);
  // Every capture of this run, oldest first.
  [[nodiscard]] std::vector<CaptureInfo> list() const;
  [[nodiscard]] Result<CaptureInfo> info(const std::string& id) const;
  // Stops every capture, each committed and closed (SIGTERM).
  void stop_all();
  // Writes the capture in `format` to a file beside it and returns that file's path
  // (sqlite: the capture itself, once stopped). A stopped capture is converted once and
  // the file reused; concurrent calls each get a complete file.
  Result<std::string> export_file(const std::string& id, DownloadFormat format);

 private:
  struct Running;
  Hub& hub_;
  std::string directory_;
  CaptureLimits limits_;
  mutable std::mutex mutex_;
  std::vector<std::unique_ptr<Running>> captures_;
  std::uint64_t counter_ = 0;
};

}  // namespace rangekit::hub
