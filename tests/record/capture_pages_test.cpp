// The direct page reader of the samples table (capture_pages, sqlite_pages) against SQLite's
// own reader: the array path must hand over exactly what SQLite reads, in the same order,
// or fall back to SQLite, or fail with an error naming the damage.
#include "record/capture_pages.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <variant>

#include "rangekit/ls5/family.hpp"
#include "rangekit/record/capture.hpp"
#include "rangekit/record/format.hpp"
#include "rangekit/record/replay.hpp"
#include "rangekit/uls/family.hpp"
#include "record/fake_source.hpp"
#include "record/sqlite_handle.hpp"
#include "record/temp_dir.hpp"

namespace rangekit::record {
namespace {

using namespace testing;

// A sample (array fields) or an event as its JSON line.
using Item = std::variant<Sample, std::string>;

std::string event_text(const StreamEvent& event) {
  std::string text;
  append_jsonl(text, event);
  return text;
}

// What SQLite reads (CaptureFields::all always goes through SQLite), less the fields an
// array row leaves out.
std::vector<Item> sqlite_items(const std::string& path, const std::string& device) {
  std::vector<Item> items;
  const auto read = for_each_in_capture(
      path, device,
      [&](const Sample& sample) {
        Sample copy = sample;
        copy.source.clear();
        // The channels kept in captures only (the LS5's resolution_mm).
        if (const FamilyDescriptor* family = family_of(copy)) {
          for (std::size_t index = 0; index < family->channels.size(); ++index) {
            if (!family->channels[index].in_stream) copy.values.erase(index);
          }
        }
        copy.suspect_reason.clear();
        items.emplace_back(std::move(copy));
      },
      [&](StreamEvent&& event) { items.emplace_back(event_text(event)); }, CaptureFields::all);
  EXPECT_TRUE(read.ok()) << read.error().message;
  return items;
}

Result<std::vector<Item>> array_items(const std::string& path, const std::string& device) {
  std::vector<Item> items;
  const auto read = for_each_in_capture(
      path, device, [&](const Sample& sample) { items.emplace_back(sample); },
      [&](StreamEvent&& event) { items.emplace_back(event_text(event)); }, CaptureFields::array);
  if (!read) return read.error();
  return items;
}

// Whether the array path reads this file's pages itself (rather than falling back).
bool read_directly(const std::string& path) {
  auto database = open_database(path, false, false, IntegrityCheck::by_caller);
  EXPECT_TRUE(database.ok());
  if (!database) return false;
  EXPECT_TRUE(execute(path, database->get(), "BEGIN").ok());
  auto root = samples_pages_root(path, database->get());
  EXPECT_TRUE(root.ok());
  return root.ok() && root->has_value();
}

void expect_same_as_sqlite(const std::string& path, std::size_t samples_expected) {
  ASSERT_TRUE(read_directly(path));
  for (const std::string device : {"", "uls", "ls5"}) {
    const auto expected = sqlite_items(path, device);
    auto got = array_items(path, device);
    ASSERT_TRUE(got.ok()) << got.error().message;
    EXPECT_EQ(got->size(), expected.size()) << "device '" << device << "'";
    for (std::size_t i = 0; i < std::min(got->size(), expected.size()); ++i) {
      ASSERT_EQ((*got)[i], expected[i]) << "item " << i << ", device '" << device << "'";
    }
  }
  std::size_t direct = 0;
  ASSERT_TRUE(read_directly(path));
  auto database = open_database(path, false, false, IntegrityCheck::by_caller);
  ASSERT_TRUE(database.ok());
  ASSERT_TRUE(execute(path, database->get(), "BEGIN").ok());
  auto root = samples_pages_root(path, database->get());
  ASSERT_TRUE(root.ok() && root->has_value());
  ASSERT_TRUE(read_samples_pages(path, **root, "", [&](std::int64_t, const Sample&) { ++direct; }).ok());
  EXPECT_EQ(direct, samples_expected);
}

void run_sql(const std::string& path, const char* sql) {
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &raw), SQLITE_OK);
  Database database(raw);
  char* message = nullptr;
  const int code = sqlite3_exec(raw, sql, nullptr, nullptr, &message);
  EXPECT_EQ(code, SQLITE_OK) << (message != nullptr ? message : "");
  sqlite3_free(message);
}

std::int64_t query_integer(const std::string& path, const char* sql) {
  auto database = open_database(path, false, false, IntegrityCheck::by_caller);
  EXPECT_TRUE(database.ok());
  if (!database) return -1;
  auto query = prepare(path, database->get(), sql);
  EXPECT_TRUE(query.ok());
  if (!query || sqlite3_step(query->get()) != SQLITE_ROW) return -1;
  return sqlite3_column_int64(query->get(), 0);
}

Sample binning_with(std::size_t targets) {
  Sample sample = uls_binning();
  sample.targets.clear();
  for (std::size_t i = 0; i < targets; ++i) sample.targets.push_back({1.0 + 0.001 * static_cast<double>(i), 7});
  return sample;
}

Sample numbered(Sample sample, int i) {
  sample.time += std::chrono::milliseconds(i);
  if (sample.get(ls5::channel::code)) sample.set(ls5::channel::code, static_cast<std::uint16_t>(i % 50001));
  if (sample.get(ls5::channel::distance_mm)) sample.set(ls5::channel::distance_mm, i * 0.002);
  if (sample.get(uls::channel::distance_m))
    sample.set(uls::channel::distance_m, 0.25 * i);  // whole numbers too: stored as integers
  return sample;
}

// Every kind of sample, events between them, two sessions, two devices.
void write_mixed_capture(const std::string& path, int rounds) {
  for (int session = 0; session < 2; ++session) {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok()) << capture.error().message;
    auto suspect = ls5_result(34845, 69.69, ls5::SignalState::ok);
    suspect.suspect = true;
    suspect.suspect_reason = "jump";
    suspect.set(ls5::channel::resolution_mm, 0.002);
    Sample derivative = ls5_result(100, std::nullopt, ls5::SignalState::ok);
    derivative.kind = ls5::kind::derivative;
    derivative.set(ls5::channel::derivative_mm, -1.5);
    for (int i = 0; i < rounds; ++i) {
      for (const Sample& sample :
           {uls_averaging(), uls_binning(), uls_look_down(), uls_look_down_overflow(), uls_error(), suspect, derivative,
            ls5_result(24845, 49.69, ls5::SignalState::ok), ls5_result(65535, std::nullopt, ls5::SignalState::lost)}) {
        ASSERT_TRUE((*capture)->write(numbered(sample, i)).ok());
      }
      if (i % 50 == 0) {
        ASSERT_TRUE((*capture)->write_event(event(StreamEventKind::disconnected, "gone", 2)).ok());
      }
    }
  }
}

TEST(CapturePages, MixedCaptureReadsAsSqliteReadsIt) {
  TempDir dir;
  const auto path = dir.file("mixed.sqlite");
  write_mixed_capture(path, 30);
  expect_same_as_sqlite(path, 2 * 30 * 9);
}

// Enough rows for interior pages: the root is a table interior page (0x05).
TEST(CapturePages, MultiLevelTreeReadsAsSqliteReadsIt) {
  TempDir dir;
  const auto path = dir.file("deep.sqlite");
  write_mixed_capture(path, 3000);
  const auto root = query_integer(path, "SELECT rootpage FROM sqlite_schema WHERE name = 'samples'");
  const auto page_size = query_integer(path, "PRAGMA page_size");
  const auto content = read_file(path);
  ASSERT_GT(content.size(), static_cast<std::size_t>(root * page_size));
  EXPECT_EQ(static_cast<std::uint8_t>(content[static_cast<std::size_t>((root - 1) * page_size)]), 0x05);
  expect_same_as_sqlite(path, 2 * 3000 * 9);
}

// A binning sample with thousands of targets: its targets text is longer than a page, the
// record continues in a chain of overflow pages.
TEST(CapturePages, RecordsWithOverflowPagesReadAsSqliteReadsThem) {
  TempDir dir;
  const auto path = dir.file("overflow.sqlite");
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok());
    for (const std::size_t targets : {1U, 100U, 200U, 3000U, 0U, 10000U}) {
      ASSERT_TRUE((*capture)->write(binning_with(targets)).ok());
      ASSERT_TRUE((*capture)->write(uls_averaging()).ok());
    }
  }
  EXPECT_GT(query_integer(path, "SELECT max(length(targets)) FROM samples"),
            3 * query_integer(path, "PRAGMA page_size"));
  expect_same_as_sqlite(path, 12);
}

// Deleted rows leave free-list pages and freeblocks behind (no VACUUM).
TEST(CapturePages, DeletedRowsAndFreePagesReadAsSqliteReadsThem) {
  TempDir dir;
  const auto path = dir.file("deleted.sqlite");
  write_mixed_capture(path, 1000);
  run_sql(path, "DELETE FROM samples WHERE seq % 3 = 0 OR (seq > 2000 AND seq < 9000)");
  EXPECT_GT(query_integer(path, "PRAGMA freelist_count"), 0);
  expect_same_as_sqlite(path, static_cast<std::size_t>(query_integer(path, "SELECT count(*) FROM samples")));
}

// A writer still open: its rows are in the write-ahead log, not yet in the file's pages.
TEST(CapturePages, AnOpenWriterMakesTheArrayPathFallBackToSqlite) {
  TempDir dir;
  const auto path = dir.file("live.sqlite");
  auto capture = open_capture(path);
  ASSERT_TRUE(capture.ok());
  for (int i = 0; i < 100; ++i) ASSERT_TRUE((*capture)->write(numbered(uls_averaging(), i)).ok());
  ASSERT_TRUE((*capture)->flush().ok());
  EXPECT_FALSE(read_directly(path));
  auto got = array_items(path, "");
  ASSERT_TRUE(got.ok()) << got.error().message;
  EXPECT_EQ(*got, sqlite_items(path, ""));
  EXPECT_EQ(got->size(), 100U);
}

// A samples table of another shape (here: a column more) is not read from its pages.
TEST(CapturePages, AnotherSchemaFallsBackToSqlite) {
  TempDir dir;
  const auto path = dir.file("altered.sqlite");
  write_mixed_capture(path, 2);
  run_sql(path, "ALTER TABLE samples ADD COLUMN extra TEXT");
  EXPECT_FALSE(read_directly(path));
  auto got = array_items(path, "");
  ASSERT_TRUE(got.ok()) << got.error().message;
  EXPECT_EQ(*got, sqlite_items(path, ""));
}

// Damage anywhere in the samples' pages is an error naming the file, never a crash or hang.
TEST(CapturePages, DamagedPagesAreErrorsNamingTheFile) {
  TempDir dir;
  const auto clean = dir.file("clean.sqlite");
  write_mixed_capture(clean, 400);
  const auto page_size = static_cast<std::size_t>(query_integer(clean, "PRAGMA page_size"));
  const auto root =
      static_cast<std::size_t>(query_integer(clean, "SELECT rootpage FROM sqlite_schema WHERE name = 'samples'"));
  const auto original = read_file(clean);
  const auto path = dir.file("damaged.sqlite");
  const auto expect_error = [&](const std::string& content, const std::string& what) {
    write_file(path, content);
    auto got = array_items(path, "");
    ASSERT_FALSE(got.ok()) << what;
    EXPECT_EQ(got.error().code, Errc::io) << what;
    EXPECT_NE(got.error().message.find(path), std::string::npos) << got.error().message;
    EXPECT_NE(got.error().message.find("corrupt"), std::string::npos) << got.error().message;
  };
  const std::size_t root_offset = (root - 1) * page_size;
  ASSERT_EQ(static_cast<std::uint8_t>(original[root_offset]), 0x05);
  const auto byte = [&original](std::size_t offset) { return static_cast<std::uint8_t>(original[offset]); };
  const std::size_t first_cell = root_offset + ((byte(root_offset + 12) << 8U) | byte(root_offset + 13));
  const std::size_t first_child = (static_cast<std::size_t>(byte(first_cell)) << 24U) |
                                  (static_cast<std::size_t>(byte(first_cell + 1)) << 16U) |
                                  (static_cast<std::size_t>(byte(first_cell + 2)) << 8U) | byte(first_cell + 3);
  const std::size_t leaf = (first_child - 1) * page_size;
  ASSERT_EQ(byte(leaf), 0x0D);
  {
    std::string loop = original;  // the root's right-most child is the root itself
    loop[root_offset + 8] = 0;
    loop[root_offset + 9] = 0;
    loop[root_offset + 10] = static_cast<char>(root >> 8U);
    loop[root_offset + 11] = static_cast<char>(root & 0xFFU);
    expect_error(loop, "loop");
  }
  {
    std::string beyond = original;  // a child past the end of the file
    for (int i = 8; i < 12; ++i) beyond[root_offset + static_cast<std::size_t>(i)] = static_cast<char>(0x7F);
    expect_error(beyond, "beyond");
  }
  {
    std::string type = original;  // garbage over the first leaf
    for (std::size_t i = 0; i < page_size; ++i) type[leaf + i] = static_cast<char>(0xA5);
    expect_error(type, "garbage page");
  }
  {
    std::string cell = original;  // a cell pointer past the page
    cell[leaf + 8] = static_cast<char>(0xFF);
    cell[leaf + 9] = static_cast<char>(0xF0);
    expect_error(cell, "cell offset");
  }
  // Truncated: the samples' last pages are gone.
  expect_error(original.substr(0, original.size() / 2), "truncated");
}

}  // namespace
}  // namespace rangekit::record
