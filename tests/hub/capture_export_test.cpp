// Capture downloads (CaptureManager::export_file, docs/api.md): exports running at once
// each get a complete file, a stopped capture is converted once and its file reused, and
// a running capture is converted afresh every time.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <latch>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "hub/site_fixture.hpp"
#include "rangekit/hub/captures.hpp"
#include "rangekit/hub/hub.hpp"
#include "rangekit/record/replay.hpp"

namespace capture_export_test {

using namespace rangekit;
using namespace std::chrono_literals;
using hub::DownloadFormat;

constexpr std::array<DownloadFormat, 3> converted_formats = {DownloadFormat::csv, DownloadFormat::jsonl,
                                                             DownloadFormat::log};

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::size_t lines(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

struct Identity {
  ino_t inode = 0;
  timespec modified{};
  bool operator==(const Identity& other) const {
    return inode == other.inode && modified.tv_sec == other.modified.tv_sec &&
           modified.tv_nsec == other.modified.tv_nsec;
  }
};

Identity identity(const std::string& path) {
  struct stat status {};
  EXPECT_EQ(::stat(path.c_str(), &status), 0) << path;
  return {status.st_ino, status.st_mtim};
}

// A capture of every ULS of the site (each format, .log included, has a layout for them),
// running until it holds at least `samples`.
struct Capturing {
  hub_test::Site site;
  std::unique_ptr<hub::Hub> hub = hub::Hub::start(site.config);
  std::string directory = (site.temp.path / "captures").string();
  hub::CaptureManager captures{*hub, directory};
  std::string id;

  explicit Capturing(std::size_t samples) {
    const std::vector<std::string> ulses = {"silo", "bay-A", "bay-B", "bay-C", "bay-D"};
    auto started = captures.start(ulses);
    EXPECT_TRUE(started.ok()) << (started.ok() ? "" : started.error().message);
    if (!started) return;
    id = started->id;
    // Subscribed after the capture: every sample seen here is queued for it too.
    auto seen = hub->subscribe("", 4096, hub::OverflowPolicy::drop_oldest);
    EXPECT_TRUE(seen.ok());
    if (!seen) return;
    std::size_t count = 0;
    const auto deadline = std::chrono::steady_clock::now() + 60s;  // a safety net; take() waits
    while (count < samples && std::chrono::steady_clock::now() < deadline) {
      for (const hub::HubItemPtr& item : (*seen)->take(256, 200ms)) {
        const bool uls = std::find(ulses.begin(), ulses.end(), item->sensor) != ulses.end();
        if (uls && std::holds_alternative<Sample>(item->item)) ++count;
      }
    }
    EXPECT_GE(count, samples);
  }

  hub::CaptureInfo stop() {
    auto stopped = captures.stop(id);
    EXPECT_TRUE(stopped.ok());
    return stopped ? *stopped : hub::CaptureInfo{};
  }

  std::vector<std::string> leftovers() const {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(directory)) {
      const std::string name = entry.path().filename().string();
      if (name.find(".part") != std::string::npos) names.push_back(name);
    }
    return names;
  }
};

struct Export {
  bool ok = false;
  std::string error;
  std::string text;
};

// `threads` calls per format, all released at once; each reads its file as soon as it has it.
std::vector<std::vector<Export>> export_at_once(hub::CaptureManager& captures, const std::string& id,
                                                const std::vector<DownloadFormat>& formats, std::size_t threads) {
  std::vector<std::vector<Export>> results(formats.size(), std::vector<Export>(threads));
  std::latch go(static_cast<std::ptrdiff_t>(formats.size() * threads));
  std::vector<std::thread> running;
  for (std::size_t f = 0; f < formats.size(); ++f) {
    for (std::size_t t = 0; t < threads; ++t) {
      running.emplace_back([&, f, t] {
        go.arrive_and_wait();
        auto file = captures.export_file(id, formats[f]);
        Export& result = results[f][t];
        result.ok = file.ok();
        if (file) result.text = contents(*file);
        if (!file) result.error = file.error().message;
      });
    }
  }
  for (std::thread& thread : running) thread.join();
  return results;
}

TEST(CaptureExport, ConcurrentExportsOfAStoppedCaptureEachGetTheWholeFile) {
  Capturing capture(60);
  const hub::CaptureInfo stopped = capture.stop();
  ASSERT_GE(stopped.samples, 60u);
  const std::vector<DownloadFormat> formats(converted_formats.begin(), converted_formats.end());
  const auto results = export_at_once(capture.captures, capture.id, formats, 8);
  for (std::size_t f = 0; f < formats.size(); ++f) {
    // The reference: a conversion made alone, after the file the threads shared is gone.
    auto first = capture.captures.export_file(capture.id, formats[f]);
    ASSERT_TRUE(first.ok()) << first.error().message;
    ASSERT_TRUE(std::filesystem::remove(*first));
    auto alone = capture.captures.export_file(capture.id, formats[f]);
    ASSERT_TRUE(alone.ok()) << alone.error().message;
    const std::string reference = contents(*alone);
    for (const Export& result : results[f]) {
      ASSERT_TRUE(result.ok) << result.error;
      EXPECT_EQ(result.text.size(), reference.size()) << *alone;
      EXPECT_TRUE(result.text == reference) << *alone;
    }
    if (formats[f] == DownloadFormat::csv) {
      EXPECT_EQ(lines(reference), stopped.samples + 1);  // and the header
    }
    if (formats[f] == DownloadFormat::jsonl) {
      EXPECT_EQ(lines(reference), stopped.samples + stopped.events);
    }
  }
  EXPECT_TRUE(capture.leftovers().empty());
}

TEST(CaptureExport, AStoppedCaptureIsConvertedOnceAndAgainOnlyWhenWrittenSince) {
  Capturing capture(5);
  const hub::CaptureInfo stopped = capture.stop();
  auto first = capture.captures.export_file(capture.id, DownloadFormat::csv);
  ASSERT_TRUE(first.ok()) << first.error().message;
  const Identity made = identity(*first);
  const std::string text = contents(*first);
  EXPECT_EQ(lines(text), stopped.samples + 1);
  auto second = capture.captures.export_file(capture.id, DownloadFormat::csv);
  ASSERT_TRUE(second.ok()) << second.error().message;
  EXPECT_EQ(*second, *first);
  EXPECT_TRUE(identity(*second) == made) << "converted again: a new file (inode) or a new write";
  EXPECT_EQ(contents(*second), text);

  // A file older than the capture's database is stale: converted again, to the same text.
  std::error_code error;
  const auto written = std::filesystem::last_write_time(stopped.path, error);
  ASSERT_FALSE(error) << error.message();
  std::filesystem::last_write_time(*first, written - 1s, error);
  ASSERT_FALSE(error) << error.message();
  auto third = capture.captures.export_file(capture.id, DownloadFormat::csv);
  ASSERT_TRUE(third.ok()) << third.error().message;
  EXPECT_NE(identity(*third).inode, made.inode);
  EXPECT_EQ(contents(*third), text);
}

TEST(CaptureExport, ARunningCaptureIsConvertedAfreshAndItsFileNeverServedOnceStopped) {
  Capturing capture(10);
  const auto results = export_at_once(capture.captures, capture.id, {DownloadFormat::csv}, 6);
  std::size_t running_lines = 0;
  for (const Export& result : results[0]) {
    ASSERT_TRUE(result.ok) << result.error;
    ASSERT_FALSE(result.text.empty());
    EXPECT_EQ(result.text.rfind("time,device,", 0), 0u);
    EXPECT_EQ(result.text.back(), '\n');
    running_lines = std::max(running_lines, lines(result.text));
  }
  auto once = capture.captures.export_file(capture.id, DownloadFormat::csv);
  ASSERT_TRUE(once.ok()) << once.error().message;
  const Identity before = identity(*once);
  auto again = capture.captures.export_file(capture.id, DownloadFormat::csv);
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_NE(identity(*again).inode, before.inode);  // running: converted afresh
  EXPECT_FALSE(capture.captures.export_file(capture.id, DownloadFormat::sqlite).ok());

  const hub::CaptureInfo stopped = capture.stop();
  auto finished = capture.captures.export_file(capture.id, DownloadFormat::csv);
  ASSERT_TRUE(finished.ok()) << finished.error().message;
  EXPECT_NE(*finished, *again);
  const std::string text = contents(*finished);
  EXPECT_EQ(lines(text), stopped.samples + 1);
  EXPECT_GE(lines(text), running_lines);
  EXPECT_TRUE(capture.leftovers().empty());
}

// What a crash in the middle of an export leaves is removed when the next run starts; the
// captures, their converted files and anything else in the folder stay.
TEST(CaptureExport, TemporaryFilesLeftByACrashAreRemovedAtStart) {
  Capturing capture(1);
  capture.stop();
  auto csv = capture.captures.export_file(capture.id, DownloadFormat::csv);
  ASSERT_TRUE(csv.ok()) << csv.error().message;
  const std::filesystem::path folder = capture.directory;
  for (const char* name : {"x.csv.part-a1B2c3", "x.jsonl.part", "x.log.part-zzzzzz", "notes.part", "x.csv.part-1"}) {
    std::ofstream(folder / name) << "partial";
  }
  hub::CaptureManager next_run(*capture.hub, capture.directory);
  std::vector<std::string> left = capture.leftovers();
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"notes.part", "x.csv.part-1"}));
  EXPECT_TRUE(std::filesystem::exists(*csv));
  EXPECT_TRUE(std::filesystem::exists(folder / (capture.id + ".sqlite")));
  EXPECT_TRUE(next_run.list().empty());
}

// The .sqlite of a stopped capture is whole on its own: the download is that one file, so
// nothing may be left in SQLite's write-ahead log beside it.
TEST(CaptureExport, AStoppedCapturesSqliteFileHoldsEverySampleWithoutItsLog) {
  Capturing capturing(40);
  const hub::CaptureInfo stopped = capturing.stop();
  auto file = capturing.captures.export_file(capturing.id, DownloadFormat::sqlite);
  ASSERT_TRUE(file.ok()) << file.error().message;
  EXPECT_FALSE(std::filesystem::exists(*file + "-wal"))
      << "left in the log: " << std::filesystem::file_size(*file + "-wal");
  // Only the file a download sends, in a folder of its own.
  const std::filesystem::path alone = capturing.site.temp.path / "downloaded.sqlite";
  std::filesystem::copy_file(*file, alone);
  auto replay = record::open_replay(alone.string(), record::ReplayOptions{0, {}});
  ASSERT_TRUE(replay.ok()) << replay.error().message;
  std::uint64_t samples = 0;
  for (;;) {
    auto item = (*replay)->next(std::chrono::milliseconds(100));
    if (!item) {
      if ((*replay)->finished()) break;
      continue;
    }
    if (std::holds_alternative<Sample>(*item)) ++samples;
  }
  EXPECT_EQ(samples, stopped.samples);
  EXPECT_GE(samples, 40u);
}

}  // namespace capture_export_test
