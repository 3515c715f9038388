// `rangekit serve --check` and `--config` (issue 13 points 1-2, docs/service.md).
#include <gtest/gtest.h>

#include <fstream>

#include "ls5_driver/cli_process.hpp"

namespace {

using ls5_driver_test::Child;
using ls5_driver_test::run_cli;
using ls5_driver_test::TempDir;

std::string write_site(const TempDir& dir, const std::string& text) {
  const auto path = (dir.path / "site.toml").string();
  std::ofstream(path) << text;
  return path;
}

TEST(Serve, CheckDescribesAGoodFileAndRefusesABadOneWithItsLine) {
  TempDir dir;
  const auto good = write_site(dir,
                               "[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\naddress = \"A\"\n"
                               "[[sensor]]\nname = \"b\"\nfamily = \"uls\"\nport = \"/dev/x\"\naddress = \"B\"\n");
  auto run = run_cli(dir.path, {"serve", "--check", good});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("2 sensors on 1 ports"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("/dev/x (115200 8N1, RS-485 bus): a b"), std::string::npos) << run.out;

  const auto bad = write_site(dir, "[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\nbuad = 9600\n");
  run = run_cli(dir.path, {"serve", "--check", bad});
  EXPECT_EQ(run.exit_code, 3);
  EXPECT_NE(run.err.find("site.toml:5: unknown key 'buad'"), std::string::npos) << run.err;

  run = run_cli(dir.path, {"serve", "--check", (dir.path / "missing.toml").string()});
  EXPECT_EQ(run.exit_code, 4);
  EXPECT_NE(run.err.find("cannot read site file"), std::string::npos) << run.err;
  EXPECT_EQ(run_cli(dir.path, {"serve"}).exit_code, 2);
}

TEST(Serve, ServesTheSiteForItsDurationAndLeavesTheSensorAsFound) {
  TempDir dir;
  const auto port = (dir.path / "ls5").string();
  Child sim({"sim", "ls5", "--port", port});
  ASSERT_NE(sim.read_line().find("ready"), std::string::npos);
  const auto site = write_site(dir, "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"" + port + "\"\n");
  const auto run = run_cli(dir.path, {"serve", "--config", site, "--duration", "1.5"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  // The last summary line: the sensor streamed and its records were counted.
  const auto last = run.out.rfind("belt ");
  ASSERT_NE(last, std::string::npos) << run.out;
  EXPECT_NE(run.out.find("ls5", last), std::string::npos);
  EXPECT_EQ(run.out.find("records 0 ", last), std::string::npos) << run.out;
  // The port is free again: a one-shot command gets the sensor's identity.
  const auto info = run_cli(dir.path, {"ls5", "info", "--port", port});
  EXPECT_EQ(info.exit_code, 0) << info.err;
}

}  // namespace
