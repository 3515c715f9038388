#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>

#include "rangekit/sim/motion.hpp"
#include "rangekit/sim/state_store.hpp"

namespace rangekit {
namespace {

using namespace std::chrono_literals;

TEST(Motion, FixedAndConstantSpeed) {
  EXPECT_DOUBLE_EQ(Motion::fixed(12.5).position_at(10s), 12.5);
  EXPECT_DOUBLE_EQ(Motion::constant_speed(10.0, -0.5).position_at(4s), 8.0);
}

TEST(Motion, PathInterpolatesClampsAndRepeats) {
  auto path = Motion::path({{0, 10}, {2, 20}, {4, 10}}, false);
  ASSERT_TRUE(path);
  EXPECT_DOUBLE_EQ(path->position_at(1s), 15.0);
  EXPECT_DOUBLE_EQ(path->position_at(3s), 15.0);
  EXPECT_DOUBLE_EQ(path->position_at(10s), 10.0);
  auto looping = Motion::path({{0, 10}, {2, 20}}, true);
  ASSERT_TRUE(looping);
  EXPECT_DOUBLE_EQ(looping->position_at(3s), 15.0);
}

TEST(Motion, BadPathsAreRefusedWithTheReason) {
  auto backwards = Motion::path({{0, 1}, {0, 2}}, false);
  ASSERT_FALSE(backwards);
  EXPECT_NE(backwards.error().message.find("point 2: times must increase"), std::string::npos);
  EXPECT_FALSE(Motion::path({}, false));
}

TEST(StateStore, SavesLoadsAndReportsCorruption) {
  const auto directory = std::filesystem::temp_directory_path() / ("rangekit-state-" + std::to_string(::getpid()));
  std::filesystem::remove_all(directory);
  StateStore store(directory.string(), "uls-Z");
  auto empty = store.load();
  ASSERT_TRUE(empty);
  EXPECT_FALSE(empty->has_value());
  ASSERT_TRUE(store.save({{"prf", 2000}}));
  auto loaded = store.load();
  ASSERT_TRUE(loaded && loaded->has_value());
  EXPECT_EQ((**loaded)["prf"], 2000);
  { std::ofstream(store.file_path()) << "{\"prf\": 20"; }
  auto corrupt = store.load();
  ASSERT_FALSE(corrupt);
  EXPECT_NE(corrupt.error().message.find("corrupt"), std::string::npos);
  std::filesystem::remove_all(directory);
}

TEST(StateStore, WithoutADirectoryNothingPersists) {
  StateStore store("", "ls5-01");
  EXPECT_FALSE(store.persistent());
  ASSERT_TRUE(store.save({{"x", 1}}));
  auto loaded = store.load();
  ASSERT_TRUE(loaded);
  EXPECT_FALSE(loaded->has_value());
}

}  // namespace
}  // namespace rangekit
