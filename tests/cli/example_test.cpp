// The library example program (examples/stream_both.cpp) runs against both
// emulators and prints readings from each.
#include <gtest/gtest.h>
#include "build_paths.hpp"
#include "cli/cli_run.hpp"

#include <filesystem>
#include <string>

#include "ls5_driver/cli_process.hpp"

namespace {

using ls5_driver_test::Child;

using cli_test::contains;

TEST(Example, StreamBothReadsEachEmulator) {
  const auto example = std::filesystem::path(rangekit::test::cli_path()).parent_path() / "examples" / "stream_both";
  if (!std::filesystem::exists(example)) GTEST_SKIP() << "example not built: " << example;
  const ls5_driver_test::TempDir temp;
  const std::filesystem::path& dir = temp.path;
  const auto uls_config = (dir / "uls-config").string();
  const auto ls5_port = (dir / "ls5").string();
  Child uls({"sim", "uls", "--port", (dir / "uls").string(), "--config-port", uls_config});
  ASSERT_TRUE(contains(uls.read_line(), "ready:"));
  Child ls5({"sim", "ls5", "--port", ls5_port});
  ASSERT_TRUE(contains(ls5.read_line(), "ready:"));

  const std::string command = example.string() + " " + uls_config + " " + ls5_port + " 1 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[4096];
  std::size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, got);
  EXPECT_EQ(::pclose(pipe), 0) << output;
  // Default scene: a wall at 50 m, read within the ±4 cm of §9.
  EXPECT_TRUE(contains(output, "uls 50.0") || contains(output, "uls 49.9")) << output;
  EXPECT_TRUE(contains(output, "LS5 LS5.")) << output;
  EXPECT_TRUE(contains(output, "ls5 ")) << output;
}

}  // namespace
