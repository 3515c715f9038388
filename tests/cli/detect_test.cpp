// `rangekit detect` against both emulators on ptys: it finds each at its baud,
// including a ULS moved off the factory rate, and names ports that are no serial port.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli/cli_run.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/sim/pty.hpp"

namespace {

using ls5_driver_test::Child;
using ls5_driver_test::run_cli;
using ls5_driver_test::TempDir;

using cli_test::contains;

TEST(Detect, FindsBothFamiliesAndAUlsOffTheFactoryBaud) {
  TempDir dir;
  const auto uls_port = (dir.path / "uls").string();
  const auto ls5_port = (dir.path / "ls5").string();
  Child uls({"sim", "uls", "--port", uls_port, "--config-port", (dir.path / "uls-config").string()});
  ASSERT_TRUE(contains(uls.read_line(), "ready:"));
  Child ls5({"sim", "ls5", "--port", ls5_port});
  ASSERT_TRUE(contains(ls5.read_line(), "ready:"));

  // §8 Set Baud Rate: the universal port (1) moves to 57600 after its $OK, which
  // still leaves at 115200 (docs/conformance.md U36), so the set itself succeeds.
  // Given first, BR is still written last: a set after it would go unanswered.
  const auto moved = run_cli(dir.path, {"uls", "set", "--port", uls_port, "BR=1,57600", "power=low"});
  ASSERT_EQ(moved.exit_code, 0) << moved.out << moved.err;
  EXPECT_LT(moved.out.find("power=low"), moved.out.find("BR=1,57600")) << moved.out;

  const auto found = run_cli(dir.path, {"detect", "--port", uls_port, "--port", ls5_port, "--jsonl"});
  EXPECT_EQ(found.exit_code, 0) << found.err;
  EXPECT_TRUE(contains(found.out, R"("baud":57600)")) << found.out;
  EXPECT_TRUE(contains(found.out, R"("family":"uls")")) << found.out;
  EXPECT_TRUE(contains(found.out, R"("family":"ls5")")) << found.out;
  EXPECT_TRUE(contains(found.out, "LS5.")) << found.out;  // the ID reply's version (§9.2)
  // Probing only reads: the ULS is still idle and still at 57600.
  const auto info = run_cli(dir.path, {"uls", "info", "--port", uls_port, "--baud", "57600"});
  EXPECT_EQ(info.exit_code, 0) << info.out << info.err;
  const auto power = run_cli(dir.path, {"uls", "get", "--port", uls_port, "--baud", "57600", "power"});
  EXPECT_TRUE(contains(power.out, "power=low")) << power.out << power.err;
}

TEST(Detect, NamesAPathThatIsNoSerialPortAndReportsNoReply) {
  TempDir dir;
  const auto missing = run_cli(dir.path, {"detect", "--port", (dir.path / "absent").string()});
  EXPECT_EQ(missing.exit_code, 4);
  EXPECT_TRUE(contains(missing.err, "absent")) << missing.err;
  const auto not_tty = run_cli(dir.path, {"detect", "--port", "/dev/null"});
  EXPECT_EQ(not_tty.exit_code, 4);
  EXPECT_TRUE(contains(not_tty.err, "not a serial port")) << not_tty.err;

  // A pty nobody answers on: each rate asked is tried, then exit 5.
  auto quiet = rangekit::PseudoTerminal::open((dir.path / "quiet").string());
  ASSERT_TRUE(quiet.ok()) << quiet.error().describe();
  const auto silent =
      run_cli(dir.path, {"detect", "--port", (*quiet)->public_path(), "--baud", "115200", "--baud", "9600"});
  EXPECT_EQ(silent.exit_code, 5) << silent.out << silent.err;
  EXPECT_TRUE(contains(silent.err, "nothing answered")) << silent.err;
}

// docs/conformance.md L66. §8.3: "The byte format for serial protocol operation specifies
// the availability of parity/odd control and the number of stop bits", table 9.2 (04)
// lists six of them. An LS5 moved to 8N2 (#01W0403) no longer understands 8N1; detect
// tries the other formats once 8N1 found nothing. Over a pty only the stop bits can be
// told apart (H2), so 8N2 is the case this test can see.
TEST(Detect, FindsAnLs5SetToAnotherByteFormatL66) {
  TempDir dir;
  const auto ls5_port = (dir.path / "ls5").string();
  Child ls5({"sim", "ls5", "--port", ls5_port});
  ASSERT_TRUE(contains(ls5.read_line(), "ready:"));
  const auto moved = run_cli(dir.path, {"ls5", "set", "--port", ls5_port, "byte-format=8N2"});
  ASSERT_EQ(moved.exit_code, 0) << moved.out << moved.err;
  const auto old_format = run_cli(dir.path, {"ls5", "info", "--port", ls5_port, "--timeout-ms", "200"});
  ASSERT_EQ(old_format.exit_code, 5) << "the sensor still answers 8N1: " << old_format.out;

  // "`--json` for `info`, `get` and `detect`" (`--jsonl` still works, above).
  const auto found = run_cli(dir.path, {"detect", "--port", ls5_port, "--baud", "115200", "--json"});
  EXPECT_EQ(found.exit_code, 0) << found.out << found.err;
  EXPECT_TRUE(contains(found.out, R"("family":"ls5")")) << found.out;
  EXPECT_TRUE(contains(found.out, R"("byte_format":"8N2")")) << found.out;
  const auto info = run_cli(dir.path, {"ls5", "info", "--port", ls5_port, "--byte-format", "8N2"});
  EXPECT_EQ(info.exit_code, 0) << info.err;
}

}  // namespace
