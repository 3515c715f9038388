#include "rangekit/hub/captures.hpp"

#include <atomic>
#include <filesystem>
#include <fstream>
#include <thread>
#include <variant>

#include "rangekit/record/capture.hpp"
#include "rangekit/record/format.hpp"
#include "rangekit/record/interface_log.hpp"
#include "rangekit/record/replay.hpp"

namespace rangekit::hub {

struct CaptureManager::Running {
  mutable std::mutex mutex;  // guards info
  CaptureInfo info;
  std::vector<SubscriptionPtr> subscriptions;
  std::unique_ptr<record::CaptureSink> sink;
  std::atomic<bool> stopping{false};
  std::thread writer;

  void run() {
    // One subscription per sensor (or one for all); each drained in turn.
    while (!stopping.load()) {
      bool wrote = false;
      for (const SubscriptionPtr& subscription : subscriptions) {
        const auto batch = subscription->take(4096, std::chrono::milliseconds(subscriptions.size() == 1 ? 100 : 20));
        wrote = write(batch) || wrote;
      }
      if (!wrote && failed()) break;
    }
    for (const SubscriptionPtr& subscription : subscriptions) {
      subscription->close();
      write(subscription->take(SIZE_MAX, std::chrono::milliseconds(0)));  // what was queued still goes in
    }
    Status flushed = sink->flush();
    std::lock_guard lock(mutex);
    for (const SubscriptionPtr& subscription : subscriptions) info.lost = subscription->lost();
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
    std::uint64_t lost = 0;
    for (const SubscriptionPtr& subscription : subscriptions) lost += subscription->lost();
    copy.lost = std::max(copy.lost, lost);
    return copy;
  }
};

Result<DownloadFormat> parse_download_format(std::string_view name) {
  if (name == "sqlite") return DownloadFormat::sqlite;
  if (name == "csv") return DownloadFormat::csv;
  if (name == "jsonl") return DownloadFormat::jsonl;
  if (name == "log") return DownloadFormat::log;
  return make_error(Errc::out_of_range, "format '" + std::string(name) + "': sqlite, csv, jsonl or log");
}

CaptureManager::CaptureManager(Hub& hub, std::string directory) : hub_(hub), directory_(std::move(directory)) {}

CaptureManager::~CaptureManager() { stop_all(); }

Result<CaptureInfo> CaptureManager::start(const std::vector<std::string>& sensors) {
  for (const std::string& name : sensors) {
    if (auto known = hub_.sensor(name); !known) return known.error();
  }
  std::error_code made;
  std::filesystem::create_directories(directory_, made);
  if (made) return make_error(Errc::io, "cannot make the capture folder " + directory_ + ": " + made.message());
  auto running = std::make_unique<Running>();
  std::lock_guard lock(mutex_);
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
  if (sensors.empty()) {
    running->subscriptions.push_back(*hub_.subscribe("", capacity, OverflowPolicy::drop_oldest));
  } else {
    for (const std::string& name : sensors) {
      running->subscriptions.push_back(*hub_.subscribe(name, capacity, OverflowPolicy::drop_oldest));
    }
  }
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
  auto capture = info(id);
  if (!capture) return capture.error();
  if (format == DownloadFormat::sqlite) {
    if (capture->active) {
      return make_error(Errc::unsupported,
                        "capture " + id + " is still running: stop it first, or download csv/jsonl/log");
    }
    return capture->path;
  }
  static constexpr const char* extensions[] = {"sqlite", "csv", "jsonl", "log"};
  const std::string path =
      (std::filesystem::path(directory_) / (id + "." + extensions[static_cast<int>(format)] + ".part")).string();
  auto source = record::open_replay(capture->path, record::ReplayOptions{0, {}});  // committed batches, full speed
  if (!source) return source.error();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return make_error(Errc::io, "cannot write " + path);
  std::string text;
  if (format == DownloadFormat::csv) text = record::csv_header();
  record::InterfaceLogWriter log;
  for (;;) {
    auto item = (*source)->next(std::chrono::milliseconds(100));
    if (!item) {
      if ((*source)->finished()) break;
      continue;
    }
    if (const auto* sample = std::get_if<Sample>(&*item)) {
      if (format == DownloadFormat::csv) record::append_csv(text, *sample);
      if (format == DownloadFormat::jsonl) record::append_jsonl(text, *sample);
      if (format == DownloadFormat::log) {
        if (Status appended = log.append(text, *sample); !appended) {
          std::filesystem::remove(path);
          return appended.error();
        }
      }
    } else if (format == DownloadFormat::jsonl) {
      record::append_jsonl(text, std::get<StreamEvent>(*item));
    }
    if (text.size() > (1u << 20)) {
      out << text;
      text.clear();
    }
  }
  out << text;
  out.close();
  if (!out) return make_error(Errc::io, "cannot write " + path);
  const std::string final_path = path.substr(0, path.size() - 5);
  std::filesystem::rename(path, final_path);
  return final_path;
}

}  // namespace rangekit::hub
