// A capture written by an earlier rangekit (format 3, tests/data/capture_format3.sqlite, made with
// the library of commit a0fd519, every kind of sample of both families) replays as that rangekit
// read it back: its JSON lines and text, kept beside it, byte for byte.
#include <gtest/gtest.h>
#include "build_paths.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "rangekit/core/family.hpp"

#include "rangekit/record/capture.hpp"
#include "rangekit/record/format.hpp"
#include "rangekit/record/replay.hpp"
#include "temp_dir.hpp"

namespace rangekit::record {
namespace {

const std::filesystem::path data = std::filesystem::path(rangekit::test::source_dir()) / "tests" / "data";

struct Read {
  std::string jsonl;
  std::string text;
};

Read replayed(const std::string& path, CaptureFields fields = CaptureFields::all) {
  Read read;
  const auto status = for_each_in_capture(
      path, "",
      [&](const Sample& sample) {
        append_jsonl(read.jsonl, sample);
        append_text(read.text, sample);
      },
      [&](StreamEvent&& event) {
        append_jsonl(read.jsonl, event);
        append_text(read.text, event);
      },
      fields);
  EXPECT_TRUE(status) << status.error().message;
  return read;
}

std::string copy_of_old_capture(const testing::TempDir& dir) {
  const std::string path = dir.file("old.sqlite");
  std::filesystem::copy_file(data / "capture_format3.sqlite", path);
  return path;
}

TEST(OldCapture, ReplaysAsTheRangekitThatWroteItReadIt) {
  const testing::TempDir dir;
  const auto read = replayed(copy_of_old_capture(dir));
  EXPECT_EQ(read.jsonl, testing::read_file((data / "capture_format3.sqlite.jsonl").string()));
  EXPECT_EQ(read.text, testing::read_file((data / "capture_format3.sqlite.txt").string()));
}

// The reading of arrays (Python's rangekit.capture) takes the SQLite path for an old schema: the
// same samples, but for the fields an array leaves out.
TEST(OldCapture, ArraysReadTheSameDistances) {
  const testing::TempDir dir;
  const auto path = copy_of_old_capture(dir);
  std::vector<std::optional<double>> all;
  std::vector<std::optional<double>> arrays;
  for (auto* into : {&all, &arrays}) {
    const auto status = for_each_in_capture(
        path, "",
        [&](const Sample& sample) {
          const auto reading = reading_of(sample);
          into->push_back(reading ? std::optional(reading->value) : std::nullopt);
        },
        [](StreamEvent&&) {}, into == &all ? CaptureFields::all : CaptureFields::array);
    ASSERT_TRUE(status) << status.error().message;
  }
  EXPECT_EQ(all.size(), 13U);
  EXPECT_EQ(all, arrays);
}

// A session appended to it makes it format 4 (its new columns NULL in the old rows), and the old
// rows still read as they did.
TEST(OldCapture, TakesANewSessionAndKeepsItsRows) {
  const testing::TempDir dir;
  const auto path = copy_of_old_capture(dir);
  const auto before = replayed(path);
  {
    auto capture = open_capture(path);
    ASSERT_TRUE(capture) << capture.error().message;
    std::vector<Sample> samples;
    ASSERT_TRUE(for_each_in_capture(
        path, "", [&](const Sample& sample) { samples.push_back(sample); }, [](StreamEvent&&) {}));
    ASSERT_FALSE(samples.empty());
    ASSERT_TRUE((*capture)->write(samples.back()));
  }
  const auto after = replayed(path);
  ASSERT_GT(after.jsonl.size(), before.jsonl.size());
  EXPECT_EQ(after.jsonl.substr(0, before.jsonl.size()), before.jsonl);
}

}  // namespace
}  // namespace rangekit::record
