#include "rangekit/hub/captures.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <system_error>
#include <thread>
#include <variant>

#include "rangekit/core/family.hpp"
#include "rangekit/record/capture.hpp"
#include "rangekit/record/format.hpp"
#include "rangekit/record/replay.hpp"

namespace rangekit::hub {

struct CaptureManager::Running {
  mutable std::mutex mutex;  // guards info
  CaptureInfo info;
  SubscriptionPtr subscription;  // its sensors' items, or every sensor's
  std::unique_ptr<record::CaptureSink> sink;
  std::atomic<bool> stopping{false};
  std::thread writer;
  std::array<std::mutex, 4> converting;  // per DownloadFormat: one conversion of a stopped capture at a time

  void run() {
    while (!stopping.load()) {
      const bool wrote = write(subscription->take(4096, std::chrono::milliseconds(100)));
      if (!wrote && failed()) break;
    }
    subscription->close();
    write(subscription->take(SIZE_MAX, std::chrono::milliseconds(0)));  // what was queued still goes in
    Status flushed = sink->flush();
    // Closed here, not at the service's exit: closing folds SQLite's write-ahead log into the
    // .sqlite file and marks the session ended, so a download of the stopped capture is whole.
    sink.reset();
    std::lock_guard lock(mutex);
    info.lost = subscription->lost();
    if (!flushed && info.error.empty()) info.error = flushed.error().message;
  }

  bool failed() const {
    std::lock_guard lock(mutex);
    return !info.error.empty();
  }

  bool write(const std::vector<HubItemPtr>& batch) {
    if (batch.empty() || failed()) return false;
    std::uint64_t samples = 0;
    std::uint64_t events = 0;
    for (const HubItemPtr& item : batch) {
      Status written = std::visit(
          [&](const auto& value) -> Status {
            if constexpr (std::is_same_v<std::decay_t<decltype(value)>, Sample>) {
              ++samples;
              return sink->write(value);
            } else {
              ++events;
              return sink->write_event(value);
            }
          },
          item->item);
      if (!written) {
        std::lock_guard lock(mutex);
        info.error = written.error().message;  // disk full: what was committed stays readable
        return false;
      }
    }
    std::lock_guard lock(mutex);
    info.samples += samples;
    info.events += events;
    return true;
  }

  CaptureInfo snapshot() const {
    std::lock_guard lock(mutex);
    CaptureInfo copy = info;
    copy.lost = std::max(copy.lost, subscription->lost());
    return copy;
  }
};

namespace {

constexpr std::array<const char*, 4> extensions = {"sqlite", "csv", "jsonl", "log"};

std::string reason(int error) { return std::error_code(error, std::generic_category()).message(); }

// "<id>.csv.part-XXXXXX" (mkostemp's six characters), or "<id>.csv.part" as written before.
bool is_export_temporary(const std::string& name) {
  std::string_view rest = name;
  if (const auto at = rest.rfind(".part-"); at != std::string_view::npos && rest.size() == at + 12) {
    rest = rest.substr(0, at + 5);
  }
  if (!rest.ends_with(".part")) return false;
  rest.remove_suffix(5);
  return rest.ends_with(".csv") || rest.ends_with(".jsonl") || rest.ends_with(".log");
}

// A conversion is reused while nothing wrote the capture after it: its database, nor the WAL
// its commits go to while the sink holds it open. Equal times count as current: nothing
// writes a stopped capture, and a clock tick (a few ms on ext4) would otherwise miss it.
bool is_current(const std::string& converted, const std::string& capture) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(converted, error)) return false;
  const auto made = std::filesystem::last_write_time(converted, error);
  if (error) return false;
  for (const std::string& written : {capture, capture + "-wal"}) {
    const auto changed = std::filesystem::last_write_time(written, error);
    if (error) {
      if (written == capture || error != std::errc::no_such_file_or_directory) return false;
      continue;
    }
    if (changed > made) return false;
  }
  return true;
}

Status write_all(int fd, std::string_view text, const std::string& path) {
  while (!text.empty()) {
    const ssize_t wrote = ::write(fd, text.data(), text.size());
    if (wrote < 0 && errno == EINTR) continue;
    if (wrote < 0) return make_error(Errc::io, "cannot write " + path + ": " + reason(errno));
    text.remove_prefix(static_cast<std::size_t>(wrote));
  }
  return ok_status();
}

// The sample in its family's own capture file; a family without one refuses the download.
Status append_program_log(std::map<std::string, std::unique_ptr<SampleWriter>, std::less<>>& logs, std::string& text,
                          const Sample& sample) {
  auto found = logs.find(sample.device);
  if (found == logs.end()) {
    const FamilyDescriptor* family = find_family(sample.device);
    if (family == nullptr || family->program_log == nullptr) {
      return make_error(Errc::unsupported, "a " + sample.device +
                                               " capture has no .log layout (that is the capture file of a "
                                               "family's own PC program); download it as sqlite, csv or jsonl");
    }
    found = logs.emplace(sample.device, family->program_log()).first;
  }
  return found->second->append(text, sample);
}

Status write_converted(SampleSource& source, DownloadFormat format, int fd, const std::string& path) {
  std::string text;
  if (format == DownloadFormat::csv) text = record::csv_header();
  std::map<std::string, std::unique_ptr<SampleWriter>, std::less<>> logs;  // a writer per family
  for (;;) {
    auto item = source.next(std::chrono::milliseconds(100));
    if (!item) {
      if (source.finished()) break;
      continue;
    }
    if (const auto* sample = std::get_if<Sample>(&*item)) {
      if (format == DownloadFormat::csv) record::append_csv(text, *sample);
      if (format == DownloadFormat::jsonl) record::append_jsonl(text, *sample);
      if (format == DownloadFormat::log) {
        if (Status appended = append_program_log(logs, text, *sample); !appended) return appended;
      }
    } else if (format == DownloadFormat::jsonl) {
      record::append_jsonl(text, std::get<StreamEvent>(*item));
    }
    if (text.size() > (1u << 20)) {
      if (Status written = write_all(fd, text, path); !written) return written;
      text.clear();
    }
  }
  return write_all(fd, text, path);
}

// Each conversion writes a file of its own (O_EXCL) and renames it onto `path`: a reader
// that opened the previous file keeps it whole. No fsync: a file is only served by the run
// that made it.
Result<std::string> convert(const std::string& capture, DownloadFormat format, const std::string& path) {
  auto source = record::open_replay(capture, record::ReplayOptions{0, {}});  // committed batches, full speed
  if (!source) return source.error();
  std::string temporary = path + ".part-XXXXXX";
  const int fd = ::mkostemp(temporary.data(), O_CLOEXEC);
  if (fd < 0) return make_error(Errc::io, "cannot create a temporary file for " + path + ": " + reason(errno));
  Status written = write_converted(**source, format, fd, temporary);
  if (::close(fd) != 0 && written) written = make_error(Errc::io, "cannot write " + temporary + ": " + reason(errno));
  if (written) {
    std::error_code renamed;
    std::filesystem::rename(temporary, path, renamed);
    if (!renamed) return path;
    written = make_error(Errc::io, "cannot rename " + temporary + " to " + path + ": " + renamed.message());
  }
  std::error_code ignored;
  std::filesystem::remove(temporary, ignored);
  return written.error();
}

}  // namespace

Result<DownloadFormat> parse_download_format(std::string_view name) {
  if (name == "sqlite") return DownloadFormat::sqlite;
  if (name == "csv") return DownloadFormat::csv;
  if (name == "jsonl") return DownloadFormat::jsonl;
  if (name == "log") return DownloadFormat::log;
  return make_error(Errc::out_of_range, "format '" + std::string(name) + "': sqlite, csv, jsonl or log");
}

CaptureManager::CaptureManager(Hub& hub, std::string directory, CaptureLimits limits)
    : hub_(hub), directory_(std::move(directory)), limits_(limits) {
  // An export cut short by a crash leaves its temporary file; no other run uses it.
  std::error_code error;
  for (std::filesystem::directory_iterator entry(directory_, error), end; !error && entry != end;
       entry.increment(error)) {
    std::error_code ignored;
    if (is_export_temporary(entry->path().filename().string())) std::filesystem::remove(entry->path(), ignored);
  }
}

CaptureManager::~CaptureManager() { stop_all(); }

Result<CaptureInfo> CaptureManager::start(const std::vector<std::string>& sensors) {
  for (const std::string& name : sensors) {
    if (auto known = hub_.sensor(name); !known) return known.error();
  }
  std::error_code made;
  std::filesystem::create_directories(directory_, made);
  if (made) return make_error(Errc::io, "cannot make the capture folder " + directory_ + ": " + made.message());
  std::error_code asked;
  const auto space = std::filesystem::space(directory_, asked);
  if (!asked && space.available < limits_.min_free_bytes) {
    return make_error(Errc::limit, "the capture folder " + directory_ + " has " +
                                       std::to_string(space.available >> 20) +
                                       " MiB free, and a capture starts only with " +
                                       std::to_string(limits_.min_free_bytes >> 20) + " MiB free or more");
  }
  auto running = std::make_unique<Running>();
  std::lock_guard lock(mutex_);
  const auto active = std::count_if(captures_.begin(), captures_.end(),
                                    [](const std::unique_ptr<Running>& capture) { return !capture->stopping.load(); });
  if (static_cast<std::size_t>(active) >= limits_.running) {
    return make_error(Errc::limit, std::to_string(active) +
                                       " captures are running, as many as the service runs at once: stop one first");
  }
  const auto now = std::chrono::system_clock::now();
  const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  std::array<char, 32> stamp{};
  std::strftime(stamp.data(), stamp.size(), "%Y%m%d-%H%M%S", &utc);
  running->info.id = std::string(stamp.data()) + "-" + std::to_string(++counter_);
  running->info.sensors = sensors;
  running->info.path = (std::filesystem::path(directory_) / (running->info.id + ".sqlite")).string();
  running->info.started = now;
  running->info.active = true;
  auto sink = record::open_capture(running->info.path);
  if (!sink) return sink.error();
  running->sink = std::move(*sink);
  // Subscribed before the first item: a capture holds a minute at 1 kHz before it loses any.
  const std::size_t capacity = 65536;
  // One queue for all its sensors: the writer waits on one queue, not on each sensor's in turn.
  running->subscription = *hub_.subscribe(sensors, capacity, OverflowPolicy::drop_oldest);
  Running* raw = running.get();
  running->writer = std::thread([raw] { raw->run(); });
  captures_.push_back(std::move(running));
  return raw->snapshot();
}

Result<CaptureInfo> CaptureManager::stop(const std::string& id) {
  Running* found = nullptr;
  {
    std::lock_guard lock(mutex_);
    for (const auto& running : captures_) {
      if (running->info.id == id) found = running.get();
    }
  }
  if (found == nullptr) return make_error(Errc::unknown_parameter, "no capture '" + id + "'");
  if (!found->stopping.exchange(true)) {
    if (found->writer.joinable()) found->writer.join();
    std::lock_guard lock(found->mutex);
    found->info.active = false;
    found->info.stopped = std::chrono::system_clock::now();
  }
  return found->snapshot();
}

std::vector<CaptureInfo> CaptureManager::list() const {
  std::lock_guard lock(mutex_);
  std::vector<CaptureInfo> all;
  for (const auto& running : captures_) all.push_back(running->snapshot());
  return all;
}

Result<CaptureInfo> CaptureManager::info(const std::string& id) const {
  std::lock_guard lock(mutex_);
  for (const auto& running : captures_) {
    if (running->info.id == id) return running->snapshot();
  }
  return make_error(Errc::unknown_parameter, "no capture '" + id + "'");
}

void CaptureManager::stop_all() {
  std::vector<std::string> ids;
  for (const CaptureInfo& capture : list()) {
    if (capture.active) ids.push_back(capture.id);
  }
  for (const std::string& id : ids) (void)stop(id);
}

Result<std::string> CaptureManager::export_file(const std::string& id, DownloadFormat format) {
  Running* running = nullptr;
  {
    std::lock_guard lock(mutex_);
    for (const auto& capture : captures_) {
      if (capture->info.id == id) running = capture.get();
    }
  }
  if (running == nullptr) return make_error(Errc::unknown_parameter, "no capture '" + id + "'");
  const CaptureInfo capture = running->snapshot();
  if (format == DownloadFormat::sqlite) {
    if (capture.active) {
      return make_error(Errc::unsupported,
                        "capture " + id + " is still running: stop it first, or download csv/jsonl/log");
    }
    return capture.path;
  }
  const std::string extension = extensions[static_cast<int>(format)];
  // A running capture's conversion lacks what comes next: it never takes the name a stopped one reuses.
  const std::string path =
      (std::filesystem::path(directory_) / (id + (capture.active ? ".active." : ".") + extension)).string();
  if (capture.active) return convert(capture.path, format, path);
  // Concurrent downloads of a stopped capture wait for one conversion, then share its file.
  std::lock_guard converting(running->converting[static_cast<int>(format)]);
  if (is_current(path, capture.path)) return path;
  return convert(capture.path, format, path);
}

}  // namespace rangekit::hub
