// U100: the ULS Interface Program's capture file (§2 File Menu), columns typed from the
// document: "Averaging Mode: Time (H:M:S:mS), Distance, Units, Intensity. Binning Mode: Time
// (H:M:S:mS), Index value in array, Number of Targets, Distance, Units. Look Down Mode:
// (H:M:S:mS), ON/OFF."
#include "rangekit/uls/interface_log.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/uls/family.hpp"

#include <gtest/gtest.h>

namespace {

using namespace rangekit;
using namespace std::chrono;

Sample uls(SampleKind kind) {
  Sample sample;
  sample.device = "uls";
  sample.kind = kind;
  // 2026-12-01 13:04:05.123 UTC
  sample.time = system_clock::time_point(seconds(1796130245) + milliseconds(123));
  return sample;
}

TEST(InterfaceLog, U100_EachModeWithItsColumns) {
  uls::InterfaceLogWriter writer;
  std::string out;
  Sample averaging = uls(uls::kind::averaging);
  averaging.set(uls::channel::distance_m, 12.345);
  averaging.set(uls::channel::pulse_width_ps, 18000);
  ASSERT_TRUE(writer.append(out, averaging));
  averaging.set(uls::channel::pulse_width_ps, std::nullopt);
  ASSERT_TRUE(writer.append(out, averaging));
  Sample binning = uls(uls::kind::binning);
  binning.targets = {{10.5, 3}, {20.25, 1}};
  ASSERT_TRUE(writer.append(out, binning));
  Sample look_down = uls(uls::kind::look_down);
  look_down.set(uls::channel::presence, true);
  ASSERT_TRUE(writer.append(out, look_down));
  look_down.set(uls::channel::presence, false);
  ASSERT_TRUE(writer.append(out, look_down));
  Sample error = uls(uls::kind::error);
  error.set(uls::channel::error, 4);
  ASSERT_TRUE(writer.append(out, error));
  EXPECT_EQ(out,
            "Time (H:M:S:mS), Distance, Units, Intensity\n"
            "13:04:05:123, 12.345, m, 18000\n"
            "13:04:05:123, 12.345, m, \n"
            "Time (H:M:S:mS), Index value in array, Number of Targets, Distance, Units\n"
            "13:04:05:123, 0, 2, 10.500, m\n"
            "13:04:05:123, 1, 2, 20.250, m\n"
            "Time (H:M:S:mS), ON/OFF\n"
            "13:04:05:123, ON\n"
            "13:04:05:123, OFF\n"
            "13:04:05:123, ERROR 4\n");
}

// §8 Binning Mode: "the ULS will send information for all targets in [the array,] always
// starting with index 0": $BM,0,3,... $BM,1,3,... $BM,2,3,... The log numbers them as the wire does.
TEST(InterfaceLog, U121_BinningIndexStartsAtZeroAsOnTheWire) {
  uls::InterfaceLogWriter writer;
  std::string out;
  Sample binning = uls(uls::kind::binning);
  binning.targets = {{4.572, 42}, {7.1, 13}, {9.25, 2}};
  ASSERT_TRUE(writer.append(out, binning));
  EXPECT_EQ(out,
            "Time (H:M:S:mS), Index value in array, Number of Targets, Distance, Units\n"
            "13:04:05:123, 0, 3, 4.572, m\n"
            "13:04:05:123, 1, 3, 7.100, m\n"
            "13:04:05:123, 2, 3, 9.250, m\n");
}

// A run of errors alone still starts with a column line: the factory mode's (averaging, U35).
// An error after binning stays under binning's columns.
TEST(InterfaceLog, U121_EveryFileStartsWithItsColumnLine) {
  uls::InterfaceLogWriter writer;
  std::string out;
  Sample error = uls(uls::kind::error);
  error.set(uls::channel::error, 4);
  ASSERT_TRUE(writer.append(out, error));
  ASSERT_TRUE(writer.append(out, error));
  EXPECT_EQ(out,
            "Time (H:M:S:mS), Distance, Units, Intensity\n"
            "13:04:05:123, ERROR 4\n"
            "13:04:05:123, ERROR 4\n");
  out.clear();
  uls::InterfaceLogWriter after_binning;
  Sample binning = uls(uls::kind::binning);
  binning.targets = {{4.572, 42}};
  ASSERT_TRUE(after_binning.append(out, binning));
  ASSERT_TRUE(after_binning.append(out, error));
  EXPECT_EQ(out,
            "Time (H:M:S:mS), Index value in array, Number of Targets, Distance, Units\n"
            "13:04:05:123, 0, 1, 4.572, m\n"
            "13:04:05:123, ERROR 4\n");
}

TEST(InterfaceLog, U100_AnLs5SampleHasNoLogLayout) {
  uls::InterfaceLogWriter writer;
  std::string out;
  Sample ls5;
  ls5.device = "ls5";
  ls5.kind = ls5::kind::result;
  const Status refused = writer.append(out, ls5);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code, Errc::unsupported);
  EXPECT_TRUE(out.empty());
}

}  // namespace
