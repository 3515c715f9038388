// Issue 11 point 5, "One CLI vocabulary for both families": `rangekit uls` and
// `rangekit ls5` print the same key style in info/get, accept get's names in set,
// print the same `config diff` and the same `connected` event. Expectations typed
// from the issue, docs/cli.md and the documents' tables.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "cli/cli_run.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/core/udp.hpp"

namespace {

using cli_test::contains;
using cli_test::run_cli;

// Both emulators on ptys in a fresh directory.
struct Emulators {
  ls5_driver_test::TempDir dir;
  std::string uls_port = (dir.path / "uls").string();
  std::string ls5_port = (dir.path / "ls5").string();
  std::string udp;
  std::unique_ptr<ls5_driver_test::Child> uls;
  std::unique_ptr<ls5_driver_test::Child> ls5;

  Emulators() {
    auto probe = rangekit::UdpSocket::bind(rangekit::Endpoint{"127.0.0.1", 0});
    if (probe) udp = "127.0.0.1:" + std::to_string(probe->local_endpoint().port);
    uls = std::make_unique<ls5_driver_test::Child>(std::vector<std::string>{"sim", "uls", "--port", uls_port});
    ls5 = std::make_unique<ls5_driver_test::Child>(
        std::vector<std::string>{"sim", "ls5", "--port", ls5_port, "--udp", udp, "--time-scale", "10"});
  }
  bool ready() { return contains(uls->read_line(), "ready:") && contains(ls5->read_line(), "ready:"); }
};

// "A `connected` event for both families": the ULS stream's first item is `connected`
// (host-uls.md); the LS5 serial stream and the UDP receiver say the same when their
// link first comes up.
TEST(OneVocabulary, BothFamiliesStreamsStartWithAConnectedEvent) {
  Emulators sims;
  ASSERT_TRUE(sims.ready());
  const auto uls = run_cli("uls stream --count 1 --format jsonl --port " + sims.uls_port);
  EXPECT_EQ(uls.exit_code, 0) << uls.output;
  EXPECT_TRUE(contains(uls.output, "\"event\":\"connected\"")) << uls.output;

  const auto ls5 = run_cli("ls5 stream --count 1 --format jsonl --port " + sims.ls5_port);
  EXPECT_EQ(ls5.exit_code, 0) << ls5.output;
  EXPECT_TRUE(contains(ls5.output, "\"event\":\"connected\"")) << ls5.output;
  EXPECT_TRUE(contains(ls5.output, "connected: " + sims.ls5_port + ": streaming")) << ls5.output;

  const auto udp = run_cli("ls5 udp --count 1 --format jsonl --duration 60 --udp-listen " + sims.udp);
  EXPECT_EQ(udp.exit_code, 0) << udp.output;
  EXPECT_TRUE(contains(udp.output, "\"event\":\"connected\"")) << udp.output;
}

}  // namespace
