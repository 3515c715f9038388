// Negative or huge durations, counts and timeouts are refused with exit 2 (docs/cli.md:
// "usage error ... invalid option value") before any port is opened, the message giving
// the allowed range in plain digits.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cli/cli_run.hpp"

namespace {

using cli_test::contains;
using cli_test::run_cli;

struct Case {
  std::string command;  // ends with the option; the value is appended
  std::string range;    // the range the message must name, typed from docs/cli.md
};

const std::vector<Case>& cases() {
  static const std::vector<Case> all{
      {"uls info --port /dev/null --timeout", "1 to 60000 milliseconds"},
      {"ls5 info --port /dev/null --timeout-ms", "1 to 60000 milliseconds"},
      {"detect --port /dev/null --timeout-ms", "1 to 60000 milliseconds"},
      {"uls measure --port /dev/null --count", "1 to 1000000000 samples"},
      {"uls stream --port /dev/null --count", "1 to 1000000000 samples"},
      {"ls5 stream --port /dev/null --count", "1 to 1000000000 samples"},
      {"capture --out /dev/null --uls /dev/null --count", "1 to 1000000000 samples"},
      {"uls stream --port /dev/null --duration", "0 to 31536000 seconds"},
      {"capture --out /dev/null --uls /dev/null --duration", "0 to 31536000 seconds"},
      {"demo --seconds", "0 to 31536000 seconds"},
      {"replay /dev/null --speed", "more than 0, up to 1000 times as fast as recorded"},
      {"uls stream --port /dev/null --max-speed", "more than 0, up to 1000000 m/s"},
      {"ls5 stream --port /dev/null --max-speed", "more than 0, up to 1000000 m/s"},
      {"decode ls5 /dev/null --range-mm", "more than 0, up to 1000000 mm"},
  };
  return all;
}

TEST(Numbers, NegativeValuesAreRefusedWithTheRange) {
  for (const Case& c : cases()) {
    const auto run = run_cli(c.command + " -2");
    EXPECT_EQ(run.exit_code, 2) << c.command << ": " << run.output;
    EXPECT_TRUE(contains(run.output, "-2 is out of range: give " + c.range)) << c.command << ": " << run.output;
    EXPECT_LT(run.output.size(), 400U) << "a short message, not a 300-digit bound: " << run.output;
  }
}

TEST(Numbers, HugeAndNonNumericValuesAreRefused) {
  for (const Case& c : cases()) {
    const auto huge = run_cli(c.command + " 99999999999999999999999");
    EXPECT_EQ(huge.exit_code, 2) << c.command << ": " << huge.output;
    EXPECT_TRUE(contains(huge.output, c.range)) << c.command << ": " << huge.output;
    const auto word = run_cli(c.command + " soon");
    EXPECT_EQ(word.exit_code, 2) << c.command << ": " << word.output;
    EXPECT_TRUE(contains(word.output, "'soon' is not a number: give " + c.range)) << c.command << ": " << word.output;
  }
}

TEST(Numbers, ZeroIsRefusedWhereOnlyAPositiveNumberMeansAnything) {
  const auto run = run_cli("replay /dev/null --speed 0");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_TRUE(contains(run.output, "0 is out of range: give more than 0, up to 1000")) << run.output;
}

TEST(Numbers, TheTimeScaleOfTheEmulatorIsChecked) {
  const auto run = run_cli("sim uls --port /tmp/rangekit-never --time-scale -1");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_TRUE(contains(run.output, "-1 is out of range: give 0.001 to 1000 times real time")) << run.output;
}

}  // namespace
