// The capture's `targets` column, written without nlohmann::json objects, stays the text
// of docs/capture.md: `{"distance_m": number, "strength": integer}` in that order, no
// spaces, shortest exact doubles (a whole number keeps ".0"), NaN and infinities as null.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "rangekit/record/capture.hpp"
#include "rangekit/record/replay.hpp"
#include "record/fake_source.hpp"
#include "record/temp_dir.hpp"

namespace rangekit::record {
namespace {

using namespace testing;

std::vector<std::string> stored_targets(const std::string& path) {
  std::vector<std::string> texts;
  sqlite3* database = nullptr;
  if (sqlite3_open_v2(path.c_str(), &database, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* statement = nullptr;
    if (sqlite3_prepare_v2(database, "SELECT targets FROM samples ORDER BY seq", -1, &statement, nullptr) ==
        SQLITE_OK) {
      while (sqlite3_step(statement) == SQLITE_ROW) {
        const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(statement, 0));
        texts.emplace_back(text != nullptr ? text : "<null>");
      }
    }
    sqlite3_finalize(statement);
  }
  sqlite3_close(database);
  return texts;
}

TEST(CaptureTargetsText, NumbersAreWrittenAsBeforeIncludingTheEdges) {
  const double distances[] = {4.572,
                              0.1 + 0.2,
                              1e15,
                              1e14,
                              1e-5,
                              0.0001,
                              -0.0,
                              0.0,
                              123456789.0,
                              std::nan(""),
                              std::numeric_limits<double>::infinity(),
                              1.7976931348623157e308,
                              5e-324};
  // Typed by hand: JSON numbers in the shortest round-trip form, exponent with a sign and
  // two digits beyond 1e15 or below 1e-4, a whole number with ".0".
  const std::vector<std::string> expected_numbers = {"4.572",       "0.30000000000000004",
                                                     "1e+15",       "100000000000000.0",
                                                     "1e-05",       "0.0001",
                                                     "-0.0",        "0.0",
                                                     "123456789.0", "null",
                                                     "null",        "1.7976931348623157e+308",
                                                     "5e-324"};
  TempDir dir;
  const auto path = dir.file("targets.sqlite");
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok()) << capture.error().message;
    for (const double distance : distances) {
      Sample sample = uls_binning();
      sample.targets = {{distance, 4294967295U}};
      ASSERT_TRUE((*capture)->write(sample).ok());
    }
    Sample empty = uls_binning();
    empty.targets.clear();
    ASSERT_TRUE((*capture)->write(empty).ok());
    Sample fifteen = uls_binning();
    fifteen.targets.clear();
    for (std::uint32_t i = 0; i < 15; ++i) fifteen.targets.push_back({1.5 + i, i});
    ASSERT_TRUE((*capture)->write(fifteen).ok());
  }
  const auto texts = stored_targets(path);
  ASSERT_EQ(texts.size(), expected_numbers.size() + 2);
  for (std::size_t i = 0; i < expected_numbers.size(); ++i) {
    EXPECT_EQ(texts[i], "[{\"distance_m\":" + expected_numbers[i] + ",\"strength\":4294967295}]") << "row " << i;
  }
  EXPECT_EQ(texts[expected_numbers.size()], "[]");
  EXPECT_EQ(texts.back(),
            "[{\"distance_m\":1.5,\"strength\":0},{\"distance_m\":2.5,\"strength\":1},"
            "{\"distance_m\":3.5,\"strength\":2},{\"distance_m\":4.5,\"strength\":3},"
            "{\"distance_m\":5.5,\"strength\":4},{\"distance_m\":6.5,\"strength\":5},"
            "{\"distance_m\":7.5,\"strength\":6},{\"distance_m\":8.5,\"strength\":7},"
            "{\"distance_m\":9.5,\"strength\":8},{\"distance_m\":10.5,\"strength\":9},"
            "{\"distance_m\":11.5,\"strength\":10},{\"distance_m\":12.5,\"strength\":11},"
            "{\"distance_m\":13.5,\"strength\":12},{\"distance_m\":14.5,\"strength\":13},"
            "{\"distance_m\":15.5,\"strength\":14}]");
}

// The session's `sources` lists every device and port once, also when they alternate
// (the writer now looks a pair up only when it differs from the previous sample's).
TEST(CaptureTargetsText, SourcesListEveryPortOnceWhenSamplesAlternate) {
  TempDir dir;
  const auto path = dir.file("sources.sqlite");
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture.ok()) << capture.error().message;
    for (int i = 0; i < 6; ++i) {
      Sample sample = uls_binning();
      sample.source = i % 2 == 0 ? "/dev/ttyUSB0" : "/dev/ttyUSB1";
      ASSERT_TRUE((*capture)->write(sample).ok());
    }
    Sample unnamed = uls_binning();
    unnamed.device.clear();
    unnamed.source.clear();
    ASSERT_TRUE((*capture)->write(unnamed).ok());
  }
  sqlite3* database = nullptr;
  ASSERT_EQ(sqlite3_open_v2(path.c_str(), &database, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* statement = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(database, "SELECT sources FROM sessions", -1, &statement, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_step(statement), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(statement, 0)),
               " , uls /dev/ttyUSB0, uls /dev/ttyUSB1");
  sqlite3_finalize(statement);
  sqlite3_close(database);
}

}  // namespace
}  // namespace rangekit::record
