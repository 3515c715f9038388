// Scene errors exit alike from both emulators (docs/cli.md, exit codes): 3 for a scene that
// does not decode or holds a value out of range, 4 for one that cannot be read; a NUL in a
// TOML key is printed escaped.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli/cli_run.hpp"
#include "cli/commands.hpp"
#include "ls5_driver/cli_process.hpp"

namespace {

using ls5_driver_test::run_cli;

using cli_test::contains;

struct SceneCase {
  std::string uls_scene;
  std::string ls5_scene;
  std::string expected_err;  // in both families' messages
};

TEST(SimSceneErrors, BothFamiliesExit3ForASceneThatDoesNotDecodeAnd4ForOneThatCannotBeRead) {
  const ls5_driver_test::TempDir temp;
  const std::vector<SceneCase> cases{
      {"distance_m = \n", "[target]\nposition_mm = \n", "scene.toml:"},                              // TOML syntax
      {"[[targets]]\ndistance_m = 9000\n", "[target]\nreflectivity = 7\n", "scene.toml:2"},          // out of range
      {"[[targets]]\n\"dist\\u0000ance_m\" = 3\n", "[target]\n\"posi\\u0000tion\" = 3\n", "\\x00"},  // NUL key
      {"\"\\u001b[2J\" = 1\n", "\"\\u001b[2J\" = 1\n", "\\x1b[2J"},  // an escape sequence as a key
  };
  for (const auto& scene : cases) {
    for (const std::string family : {"uls", "ls5"}) {
      const auto file = temp.path / "scene.toml";
      std::ofstream(file) << (family == "uls" ? scene.uls_scene : scene.ls5_scene);
      const auto run =
          run_cli(temp.path, {"sim", family, "--port", (temp.path / family).string(), "--scene", file.string()});
      EXPECT_EQ(run.exit_code, rangekit::cli::exit_bad_input) << family << ": " << run.err;
      EXPECT_TRUE(contains(run.err, scene.expected_err)) << family << ": " << run.err;
      EXPECT_FALSE(contains(run.err, std::string(1, '\0'))) << family << ": a raw NUL";
      EXPECT_FALSE(contains(run.err, "\x1b")) << family << ": a raw escape";
    }
  }
  for (const std::string family : {"uls", "ls5"}) {
    const auto run = run_cli(temp.path, {"sim", family, "--port", (temp.path / family).string(), "--scene",
                                         (temp.path / "missing.toml").string()});
    EXPECT_EQ(run.exit_code, rangekit::cli::exit_io) << family << ": " << run.err;
    EXPECT_TRUE(contains(run.err, "missing.toml")) << family << ": " << run.err;
  }
}

}  // namespace
