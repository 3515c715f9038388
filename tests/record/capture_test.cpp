#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <variant>

#include "child_process.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/record/capture.hpp"
#include "rangekit/record/replay.hpp"
#include "rangekit/uls/family.hpp"
#include "record/fake_source.hpp"
#include "record/temp_dir.hpp"
#include "sqlite_query.hpp"

namespace rangekit::record {
namespace {

using namespace testing;

std::vector<StreamItem> replay_all(const std::string& path, ReplayOptions options = {0.0, {}}) {
  std::vector<StreamItem> items;
  auto source = open_replay(path, options);
  EXPECT_TRUE(source.ok()) << (source.ok() ? "" : source.error().message);
  if (!source.ok()) return items;
  while (!(*source)->finished()) {
    if (auto item = (*source)->next(std::chrono::milliseconds(1000))) items.push_back(std::move(*item));
  }
  return items;
}

using sqlite_test::query;

std::vector<StreamItem> every_kind() {
  return {uls_averaging(),
          uls_binning(),
          event(StreamEventKind::disconnected, "/dev/ttyUSB0 went away"),
          uls_look_down(),
          uls_look_down_overflow(),  // U88: comes back as an overflow, not as 0 pulses
          uls_error(),
          event(StreamEventKind::lost_records, "UDP counter gap", 3),
          ls5_result(12345, 1234.5, ls5::SignalState::ok),
          ls5_result(65535, std::nullopt, ls5::SignalState::lost)};
}

void write_items(CaptureSink& capture, const std::vector<StreamItem>& items) {
  for (const auto& item : items) {
    const auto status = std::holds_alternative<Sample>(item) ? capture.write(std::get<Sample>(item))
                                                             : capture.write_event(std::get<StreamEvent>(item));
    ASSERT_TRUE(status.ok()) << status.error().message;
  }
}

void expect_same_items(const std::vector<StreamItem>& got, const std::vector<StreamItem>& expected) {
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got[i].index(), expected[i].index()) << "item " << i;
    if (const auto* sample = std::get_if<Sample>(&expected[i])) {
      EXPECT_EQ(std::get<Sample>(got[i]), *sample) << "item " << i;
    } else {
      const auto& want = std::get<StreamEvent>(expected[i]);
      const auto& have = std::get<StreamEvent>(got[i]);
      EXPECT_EQ(have.time, want.time);
      EXPECT_EQ(have.kind, want.kind);
      EXPECT_EQ(have.message, want.message);
      EXPECT_EQ(have.count, want.count);
    }
  }
}

TEST(Capture, RoundTripGivesEqualSamplesAndEventsInOrder) {
  TempDir dir;
  const auto path = dir.file("round.sqlite");
  const auto items = every_kind();
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok()) << capture.error().message;
    write_items(**capture, items);
  }
  expect_same_items(replay_all(path), items);
  EXPECT_EQ(query(path, "PRAGMA journal_mode"), "wal");
  EXPECT_EQ(query(path, "SELECT count(*) FROM samples"), "7");
  EXPECT_EQ(query(path, "SELECT count(*) FROM events"), "2");
  EXPECT_EQ(query(path, "SELECT rangekit_version FROM sessions"), "0.1.0");
  EXPECT_EQ(query(path, "SELECT sources FROM sessions"), "ls5 udp:127.0.0.1:5000, uls /dev/ttyUSB0, uls /dev/ttyUSB1");
  EXPECT_EQ(query(path, "SELECT targets FROM samples WHERE kind = 'binning'"),
            "[{\"distance_m\":4.572,\"strength\":42},{\"distance_m\":7.1,\"strength\":13}]");
}

TEST(Capture, OpeningAgainAppendsANewSession) {
  TempDir dir;
  const auto path = dir.file("twice.sqlite");
  const std::vector<StreamItem> first{uls_averaging(0ms), uls_averaging(10ms)};
  const std::vector<StreamItem> second{ls5_result(1, 0.5, ls5::SignalState::ok)};
  for (const auto* items : {&first, &second}) {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok()) << capture.error().message;
    write_items(**capture, *items);
  }
  auto all = first;
  all.insert(all.end(), second.begin(), second.end());
  expect_same_items(replay_all(path), all);
  EXPECT_EQ(query(path, "SELECT count(*) FROM sessions"), "2");
  EXPECT_EQ(query(path, "SELECT count(*) FROM samples WHERE session = 2"), "1");
}

// docs/conformance.md L60, L63: a derivative (formula 8.2) and the sensor's
// discreteness (table 3.1: 0.0001 mm for the 0.5/5 sensor) come back from the capture
// as they went in, so a replay prints the live stream's digits.
TEST(Capture, Ls5DerivativeAndResolutionRoundTripL63) {
  TempDir dir;
  const auto path = dir.file("ls5.sqlite");
  auto fine = ls5_result(21124, 2.1124, ls5::SignalState::ok);
  fine.set(ls5::channel::resolution_mm, 0.0001);
  auto rising = ls5_result(25050, std::nullopt, ls5::SignalState::ok);
  rising.kind = ls5::kind::derivative;
  rising.set(ls5::channel::derivative_mm, 0.1);
  rising.set(ls5::channel::resolution_mm, 0.001);
  const std::vector<StreamItem> items{fine, rising};
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok()) << capture.error().message;
    write_items(**capture, items);
  }
  expect_same_items(replay_all(path), items);
  EXPECT_EQ(query(path, "SELECT value FROM meta WHERE key = 'format_version'"), "4");
  EXPECT_EQ(query(path, "SELECT kind || ' ' || derivative_mm FROM samples WHERE code = 25050"), "derivative 0.1");
}

// U102/L71: the flag and its reason are stored (format version 3) and
// replayed as they were recorded.
TEST(Capture, U102_L71_SuspectFlagAndReasonRoundTrip) {
  TempDir dir;
  const auto path = dir.file("suspect.sqlite");
  auto clean = ls5_result(24845, 99.38, ls5::SignalState::ok);
  auto corrupt = ls5_result(34845, 139.38, ls5::SignalState::ok);
  corrupt.suspect = true;
  corrupt.suspect_reason = "jump: 0.1394 m from the median 0.0994 m";
  const std::vector<StreamItem> items{clean, corrupt};
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok()) << capture.error().message;
    write_items(**capture, items);
  }
  expect_same_items(replay_all(path), items);
  EXPECT_EQ(query(path, "SELECT count(*) FROM samples WHERE suspect = 1"), "1");
  EXPECT_EQ(query(path, "SELECT suspect_reason FROM samples WHERE code = 34845"),
            "jump: 0.1394 m from the median 0.0994 m");
}

// A capture written before format version 2 (schema of docs/capture.md, version 1):
// its samples replay with no resolution (2 decimals, as they were printed), and a new
// session appended to it gets the new columns.
TEST(Capture, Version1CaptureReplaysAndTakesNewSessionsL63) {
  TempDir dir;
  const auto path = dir.file("v1.sqlite");
  {
    sqlite3* database = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &database), SQLITE_OK);
    const char* v1 =
        "CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);"
        "INSERT INTO meta VALUES ('format','rangekit-capture'),('format_version','1');"
        "CREATE TABLE sessions(id INTEGER PRIMARY KEY, started TEXT NOT NULL, started_ns INTEGER NOT NULL,"
        " ended_ns INTEGER, rangekit_version TEXT NOT NULL, sources TEXT NOT NULL DEFAULT '');"
        "CREATE TABLE samples(seq INTEGER PRIMARY KEY, session INTEGER NOT NULL, time_ns INTEGER NOT NULL,"
        " device TEXT NOT NULL, source TEXT NOT NULL, address INTEGER, kind TEXT NOT NULL, distance_m REAL,"
        " pulse_width INTEGER, targets TEXT, presence INTEGER, pulses_between_events INTEGER, device_error INTEGER,"
        " code INTEGER, distance_mm REAL, signal TEXT);"
        "CREATE TABLE events(seq INTEGER PRIMARY KEY, session INTEGER NOT NULL, time_ns INTEGER NOT NULL,"
        " kind TEXT NOT NULL, message TEXT NOT NULL, count INTEGER NOT NULL);"
        "INSERT INTO sessions VALUES (1, '2026-11-26T01:02:03.456Z', 1795654923456000000, NULL, '0.1.0', '');"
        "INSERT INTO samples VALUES (1, 1, 1795654923456000000, 'ls5', 'udp:127.0.0.1:5000', NULL, 'result',"
        " NULL, NULL, NULL, NULL, NULL, NULL, 12345, 1234.5, 'ok');";
    ASSERT_EQ(sqlite3_exec(database, v1, nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(database);
    sqlite3_close(database);
  }
  const auto old_sample = ls5_result(12345, 1234.5, ls5::SignalState::ok);
  expect_same_items(replay_all(path), {old_sample});

  auto fine = ls5_result(21124, 2.1124, ls5::SignalState::ok);
  fine.set(ls5::channel::resolution_mm, 0.0001);
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok()) << capture.error().message;
    write_items(**capture, {fine});
  }
  expect_same_items(replay_all(path), {old_sample, fine});
  EXPECT_EQ(query(path, "SELECT value FROM meta WHERE key = 'format_version'"), "4");
}

// A look-down sample's kind is the mode's value name, "look-down"; captures written before
// say "look_down" and still replay as look-down samples, through SQLite and through the
// direct page reader alike, and print with today's name.
TEST(Capture, OldLookDownKindStillReplaysAsLookDown) {
  TempDir dir;
  const auto path = dir.file("old_kind.sqlite");
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok()) << capture.error().message;
    write_items(**capture, {uls_look_down(), uls_look_down_overflow()});
  }
  EXPECT_EQ(query(path, "SELECT group_concat(kind) FROM samples"), "look-down,look-down");
  {
    sqlite3* database = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &database), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(database, "UPDATE samples SET kind = 'look_down'", nullptr, nullptr, nullptr), SQLITE_OK)
        << sqlite3_errmsg(database);
    sqlite3_close(database);
  }
  expect_same_items(replay_all(path), {uls_look_down(), uls_look_down_overflow()});
  for (const auto fields : {CaptureFields::all, CaptureFields::array}) {
    std::vector<SampleKind> kinds;
    const auto read = for_each_in_capture(
        path, "", [&](const Sample& sample) { kinds.push_back(sample.kind); }, [](StreamEvent&&) {}, fields);
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(kinds, (std::vector{uls::kind::look_down, uls::kind::look_down}));
  }
}

// A format version this build does not know may hold what it would drop or misread:
// append and replay refuse it, naming the version, rather than go on without notice.
TEST(Capture, UnknownFormatVersionIsRefusedByAppendAndReplay) {
  TempDir dir;
  const auto path = dir.file("future.sqlite");
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok()) << capture.error().message;
    write_items(**capture, {uls_averaging()});
  }
  for (const char* version : {"5", "2.1", "x\x1b[2J"}) {
    sqlite3* database = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &database), SQLITE_OK);
    const std::string update = std::string("UPDATE meta SET value = '") + version + "' WHERE key = 'format_version'";
    ASSERT_EQ(sqlite3_exec(database, update.c_str(), nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(database);
    const auto content = read_file(path);

    auto capture = open_capture(path);
    ASSERT_FALSE(capture.ok()) << version;
    EXPECT_EQ(capture.error().code, Errc::unsupported);
    EXPECT_NE(capture.error().message.find("format version '"), std::string::npos) << capture.error().message;
    EXPECT_NE(capture.error().message.find("is not one this rangekit reads (1, 2, 3, 4)"), std::string::npos)
        << capture.error().message;
    EXPECT_EQ(capture.error().message.find('\x1b'), std::string::npos) << "printed escaped";
    EXPECT_EQ(read_file(path), content) << "nothing appended";

    const auto replay = open_replay(path, 0.0);
    ASSERT_FALSE(replay.ok()) << version;
    EXPECT_NE(replay.error().message.find("is not one this rangekit reads (1, 2, 3, 4)"), std::string::npos)
        << replay.error().message;
  }
  EXPECT_EQ(query(path, "SELECT count(*) FROM samples"), "1");
}

void expect_refused_untouched(const std::string& path, const std::string& content, const std::string& why) {
  auto capture = open_capture(path);
  ASSERT_FALSE(capture.ok());
  EXPECT_EQ(capture.error().code, Errc::io);
  EXPECT_NE(capture.error().message.find(path), std::string::npos) << capture.error().message;
  EXPECT_NE(capture.error().message.find(why), std::string::npos) << capture.error().message;
  EXPECT_EQ(read_file(path), content);
  EXPECT_FALSE(std::filesystem::exists(path + "-wal"));
  const auto replay = open_replay(path, 0.0);
  ASSERT_FALSE(replay.ok());
  EXPECT_NE(replay.error().message.find(path), std::string::npos) << replay.error().message;
}

TEST(Capture, TextFileIsRefusedAndLeftUntouched) {
  TempDir dir;
  const auto path = dir.file("notes.sqlite");
  const std::string content = "these are my notes, not a database\n" + std::string(2000, 'x');
  write_file(path, content);
  expect_refused_untouched(path, content, "not a rangekit capture");
}

TEST(Capture, OtherSqliteDatabaseIsRefusedAndLeftUntouched) {
  TempDir dir;
  const auto path = dir.file("other.sqlite");
  sqlite3* database = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &database), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(database, "CREATE TABLE accounts(id INTEGER); INSERT INTO accounts VALUES (1);", nullptr,
                         nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(database);
  expect_refused_untouched(path, read_file(path), "not a rangekit capture");
}

// A database whose meta row holds NULL (another program's meta table) is refused as not a
// capture, like any other database, and never read as a string.
TEST(Capture, MetaWithANullFormatIsRefusedAndLeftUntouched) {
  TempDir dir;
  const auto path = dir.file("null-meta.sqlite");
  sqlite3* database = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &database), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(database, "CREATE TABLE meta(key TEXT, value TEXT); INSERT INTO meta VALUES ('format', NULL);",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(database);
  expect_refused_untouched(path, read_file(path), "not a rangekit capture");
}

TEST(Capture, CorruptCaptureIsRefusedAndLeftUntouched) {
  TempDir dir;
  const auto path = dir.file("corrupt.sqlite");
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok());
    for (int i = 0; i < 500; ++i) write_items(**capture, {uls_averaging(std::chrono::milliseconds(i))});
  }
  auto content = read_file(path);
  ASSERT_GT(content.size(), 4 * 4096u);
  // Garbage over the third page (a b-tree page of the samples table).
  for (std::size_t i = 2 * 4096; i < 3 * 4096; ++i) content[i] = static_cast<char>(0xA5);
  write_file(path, content);
  expect_refused_untouched(path, content, "corrupt");
}

TEST(Capture, DiskFullIsAClearErrorAndKeepsCommittedBatches) {
  TempDir dir;
  const auto path = dir.file("full.sqlite");
  CaptureOptions options;
  options.batch_samples = 10;
  options.batch_interval = std::chrono::hours(1);  // commit by count only, so the test is deterministic
  options.max_page_count = 40;                     // about 160 KiB: a disk that fills up quickly
  std::uint64_t committed = 0;
  {
    auto capture = open_capture(path, options);
    ASSERT_TRUE(capture.ok()) << capture.error().message;
    Status status = ok_status();
    int written = 0;
    for (; written < 100000 && status.ok(); ++written) {
      status = (*capture)->write(uls_averaging(std::chrono::milliseconds(written)));
    }
    ASSERT_FALSE(status.ok()) << "the page limit was never reached";
    EXPECT_EQ(status.error().code, Errc::io);
    EXPECT_NE(status.error().message.find("capture " + path + ": disk full"), std::string::npos)
        << status.error().message;
    committed = (*capture)->committed_samples();
    EXPECT_GT(committed, 0u);
    EXPECT_LT(committed, static_cast<std::uint64_t>(written));
    EXPECT_FALSE((*capture)->write(uls_averaging()).ok());  // stays failed
  }
  EXPECT_EQ(query(path, "PRAGMA integrity_check"), "ok");
  EXPECT_EQ(query(path, "SELECT count(*) FROM samples"), std::to_string(committed));
  EXPECT_EQ(replay_all(path).size(), committed);
}

// The child writes continuously and reports through a pipe how many samples
// are committed; it is killed mid-batch. Everything it reported must be there.
TEST(Capture, KillNineLosesAtMostTheOpenBatch) {
  TempDir dir;
  const auto path = dir.file("killed.sqlite");
  int report[2];
  ASSERT_EQ(::pipe(report), 0);
  const pid_t child = rangekit::test::fork_child();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(report[0]);
    CaptureOptions options;
    options.batch_samples = 50;
    auto capture = open_capture(path, options);
    if (!capture.ok()) ::_exit(3);
    std::uint64_t reported = 0;
    for (std::int64_t i = 0;; ++i) {
      if (!(*capture)->write(uls_averaging(std::chrono::milliseconds(i))).ok()) ::_exit(4);
      const auto committed = (*capture)->committed_samples();
      if (committed != reported) {
        reported = committed;
        if (::write(report[1], &reported, sizeof reported) != sizeof reported) ::_exit(5);
      }
    }
  }
  ::close(report[1]);
  std::uint64_t last_reported = 0;
  int reports = 0;
  while (reports < 20) {
    pollfd readable{report[0], POLLIN, 0};
    ASSERT_GT(::poll(&readable, 1, 10000), 0) << "no progress from the writing child";
    std::uint64_t value = 0;
    ASSERT_EQ(::read(report[0], &value, sizeof value), static_cast<ssize_t>(sizeof value));
    last_reported = value;
    ++reports;
  }
  ASSERT_EQ(::kill(child, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  std::uint64_t value = 0;  // reports written before the kill landed
  while (::read(report[0], &value, sizeof value) == static_cast<ssize_t>(sizeof value)) last_reported = value;
  ::close(report[0]);

  EXPECT_EQ(query(path, "PRAGMA integrity_check"), "ok");
  EXPECT_GE(std::stoull(query(path, "SELECT count(*) FROM samples")), last_reported);
  EXPECT_GE(replay_all(path).size(), last_reported);  // read as the killed writer left it
  auto reopened = open_capture(path);                 // still a capture that takes a new session
  ASSERT_TRUE(reopened.ok()) << reopened.error().message;
  ASSERT_TRUE((*reopened)->write(uls_error()).ok());
  reopened->reset();
  EXPECT_EQ(query(path, "SELECT count(*) FROM sessions"), "2");
}

}  // namespace
}  // namespace rangekit::record
