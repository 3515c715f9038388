// Per-sample quality (conformance U101, U102, U103, L71, L72). Every
// vector is typed from the documents: the ULS §9 output shapes and accuracy, the LS5
// formula 8.1 and its ±0.15 % error limit (§3 table 3.1).
#include "rangekit/core/sample_quality.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "rangekit/ls5/driver.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/ls5/ls5.hpp"
#include "rangekit/uls/family.hpp"
#include "rangekit/uls/uls.hpp"

namespace rangekit {
namespace {

using std::chrono::milliseconds;

const auto start = std::chrono::system_clock::time_point(std::chrono::seconds(1'800'000'000));

Sample uls_reading(double distance_m, milliseconds at, std::optional<std::uint32_t> pulse_width_ps = std::nullopt) {
  Sample sample;
  sample.time = start + at;
  sample.device = "uls";
  sample.source = "/dev/ttyUSB0";
  sample.kind = uls::kind::averaging;
  sample.set(uls::channel::distance_m, distance_m);
  sample.set(uls::channel::pulse_width_ps, pulse_width_ps);
  return sample;
}

// An LS5 record as the driver makes it: code, and formula 8.1 on a 100 mm range.
Sample ls5_reading(std::uint16_t code, milliseconds at) {
  Sample sample;
  sample.time = start + at;
  sample.device = "ls5";
  sample.source = "/dev/ttyUSB1";
  sample.kind = ls5::kind::result;
  sample.set(ls5::channel::code, code);
  sample.set(ls5::channel::distance_mm, code * 100.0 / 50000.0);
  sample.set(ls5::channel::signal, ls5::SignalState::ok);
  return sample;
}

ls5::ResultCode code_of(std::uint16_t value) { return ls5::classify_result_code(value); }

uls::MeasurementContext averaging(uls::DisplayMode display, uls::Units units) {
  return {uls::Mode::averaging, display, units, false};
}

// U101: §9 "xxxx.xxx = range (meters)", "xxxx.xx = range (feet)": the field shapes are the
// codec's, so a line of the wrong shape never becomes a sample to flag. A metres field
// with 2 decimals (a dropped digit), a feet field with 3 (a duplicated one) and a pulse
// width of 8 digits (§9 "yyyyyyy") are refused.
TEST(SampleQuality, U101_WrongFieldShapesAreRefusedByTheCodecNotPassedOn) {
  using uls::DisplayMode;
  using uls::Units;
  EXPECT_FALSE(uls::decode_measurement(as_bytes("$BM,50.00"), averaging(DisplayMode::range, Units::metres)).ok());
  EXPECT_FALSE(uls::decode_measurement(as_bytes("$BM,164.042"), averaging(DisplayMode::range, Units::feet)).ok());
  EXPECT_FALSE(uls::decode_measurement(as_bytes("$BM,50.002,33000000"),
                                       averaging(DisplayMode::range_and_intensity, Units::metres))
                   .ok());
  // The same lines with the right shape pass: what they carry is judged by SampleChecker.
  EXPECT_TRUE(uls::decode_measurement(as_bytes("$BM,50.002"), averaging(DisplayMode::range, Units::metres)).ok());
  EXPECT_TRUE(uls::decode_measurement(as_bytes("$BM,164.04"), averaging(DisplayMode::range, Units::feet)).ok());
  // A digit turned into another digit keeps the shape: "$BM,58.002" for "$BM,50.002".
  EXPECT_TRUE(uls::decode_measurement(as_bytes("$BM,58.002"), averaging(DisplayMode::range, Units::metres)).ok());
}

// U102: §9 averaging accuracy "±4 cm typical": readings of a still target at 50 m within
// ±4 cm of each other are never suspect; a bit error that turns 50.002 into 58.002 (one
// digit, 8 m in 1.5 s) is, with its reason, and keeps its value, on a sensor whose targets
// move at most 2 m/s (a crane).
TEST(SampleQuality, U102_AJumpNoTargetCanMakeIsSuspect) {
  SampleChecker checker(QualitySettings{2.0});
  const std::vector<double> still{50.002, 50.031, 49.975, 50.010, 49.963, 50.039};
  for (std::size_t i = 0; i < still.size(); ++i) {
    auto sample = uls_reading(still[i], milliseconds(500 * static_cast<int>(i)));
    checker.check(sample);
    EXPECT_FALSE(sample.suspect) << still[i] << ": " << sample.suspect_reason;
  }
  auto corrupt = uls_reading(58.002, milliseconds(3000));
  checker.check(corrupt);
  EXPECT_TRUE(corrupt.suspect);
  EXPECT_EQ(corrupt.get(uls::channel::distance_m), 58.002) << "the value stays as received";
  EXPECT_NE(corrupt.suspect_reason.find("jump: 58.0020 m from the median"), std::string::npos)
      << corrupt.suspect_reason;
  // The next honest reading is not held against the corrupt one (the median ignores it).
  auto next = uls_reading(50.004, milliseconds(3500));
  checker.check(next);
  EXPECT_FALSE(next.suspect) << next.suspect_reason;
}

// U102: max_speed: a target moving at 20 m/s is 10 m further each 0.5 s; with the default
// of 25 m/s none of it is suspect; with max_speed = 5 m/s set for the sensor, it is.
TEST(SampleQuality, U102_MaxSpeedDecidesWhatJumpIsPossible) {
  SampleChecker fast;
  SampleChecker slow(QualitySettings{5.0});
  int suspect_slow = 0;
  for (int i = 0; i < 10; ++i) {
    auto sample = uls_reading(20.0 + 10.0 * i, milliseconds(500 * i));
    auto copy = sample;
    fast.check(sample);
    EXPECT_FALSE(sample.suspect) << sample.suspect_reason;
    slow.check(copy);
    suspect_slow += copy.suspect ? 1 : 0;
  }
  EXPECT_EQ(suspect_slow, 7) << "every reading once three are known";
}

// U102: a real step (a box arrives at 12 m in front of a wall at 50 m) is flagged until the
// median has moved, at most min_history readings, then the new distance is accepted.
TEST(SampleQuality, U102_ARealStepIsFlaggedOnlyUntilTheMedianMoves) {
  SampleChecker checker;
  int at = 0;
  for (int i = 0; i < 5; ++i) {
    auto sample = uls_reading(50.000, milliseconds(100 * at++));
    checker.check(sample);
  }
  int flagged = 0;
  for (int i = 0; i < 10; ++i) {
    auto sample = uls_reading(12.000, milliseconds(100 * at++));
    checker.check(sample);
    flagged += sample.suspect ? 1 : 0;
  }
  EXPECT_EQ(flagged, 3);
}

// U103: a pulse width that changes by more than a factor 2 against the recent ones (a dropped
// digit: "33000" read as "3300") is suspect; §9 gives no relation of pulse width to distance,
// so the width is only compared with itself.
TEST(SampleQuality, U103_APulseWidthOffByADigitIsSuspect) {
  SampleChecker checker;
  for (int i = 0; i < 4; ++i) {
    auto sample = uls_reading(50.002, milliseconds(500 * i), 33000);
    checker.check(sample);
    EXPECT_FALSE(sample.suspect);
  }
  auto dropped = uls_reading(50.002, milliseconds(2000), 3300);
  checker.check(dropped);
  EXPECT_TRUE(dropped.suspect);
  EXPECT_NE(dropped.suspect_reason.find("pulse width: 3300 ps"), std::string::npos) << dropped.suspect_reason;
}

// L72: the LS5 record's shape is the codec's (L1 "!ddddd", §8.9 codes 0-50000 and the two
// special values): a dropped digit, a duplicated one, or a digit turned into one that makes a
// code of 50001-65533 are refused and never reach the checks; 34845 for 24845 is well formed.
TEST(SampleQuality, L72_Ls5RecordShapesAreRefusedByTheCodec) {
  EXPECT_FALSE(ls5::parse_reply(as_bytes("!2485")).ok());
  EXPECT_FALSE(ls5::parse_reply(as_bytes("!248455")).ok());
  EXPECT_FALSE(ls5::parse_reply(as_bytes("!64845")).ok());
  EXPECT_TRUE(ls5::parse_reply(as_bytes("!34845")).ok());
}

// L71: formula 8.1 "distance = code · range / 50000" read backwards gives the range, and
// §3 table 3.1's ±0.15 % of it is the noise allowance: on a 100 mm sensor two readings may
// differ by 0.3 mm (150 codes). Code 24845 read as 34845 (one digit changed) is 20 mm.
TEST(SampleQuality, L71_Ls5CodeWithAWrongDigitIsSuspect) {
  EXPECT_DOUBLE_EQ(*ls5::range_from_result_mm(ls5_reading(24845, milliseconds(0))), 100.0);
  SampleChecker checker;
  const std::vector<std::uint16_t> codes{24845, 24900, 24790, 24870, 24820};
  for (std::size_t i = 0; i < codes.size(); ++i) {
    auto sample = ls5_reading(codes[i], milliseconds(static_cast<int>(i)));
    checker.check(sample);
    EXPECT_FALSE(sample.suspect) << codes[i] << ": " << sample.suspect_reason;
  }
  auto corrupt = ls5_reading(34845, milliseconds(5));
  checker.check(corrupt);
  EXPECT_TRUE(corrupt.suspect);
  // 24845 -> 24846 (the last digit) is within the sensor's own error: not catchable.
  auto last_digit = ls5_reading(24846, milliseconds(6));
  checker.check(last_digit);
  EXPECT_FALSE(last_digit.suspect);
}

// L71: the driver's samples (formula 8.1 applied by make_ls5_sample) give the same range.
TEST(SampleQuality, L71_RangeFromADriverSample) {
  const Sample sample = ls5::make_ls5_sample(code_of(25000), 100.0, "/dev/ttyUSB1", 1, false);
  EXPECT_DOUBLE_EQ(*ls5::range_from_result_mm(sample), 100.0);
  // §3 table 3.1: ±0.15 % of 100 mm; a code is 100 mm / 50000; the range crossed in a second.
  const auto scale = quality_input_of(sample)->scale;
  ASSERT_TRUE(scale.has_value());
  EXPECT_DOUBLE_EQ(scale->accuracy_m, 0.00015);
  EXPECT_DOUBLE_EQ(scale->resolution_m, 0.000002);
  EXPECT_DOUBLE_EQ(scale->max_speed_mps, 0.1);
}

// L71: records bunched in one read (the same receive time) are spaced by the mean interval
// so far: a target at the default top speed (the range a second, 0.1 m/s on 100 mm) moving
// 0.1 mm a millisecond is not suspect when ten records arrive at once.
TEST(SampleQuality, L71_BunchedRecordsUseTheMeanInterval) {
  SampleChecker checker;
  int flagged = 0;
  for (int i = 0; i < 200; ++i) {
    const int code = 10000 + 50 * i;  // 0.1 mm a record
    auto sample = ls5_reading(static_cast<std::uint16_t>(code), milliseconds((i / 10) * 10));
    checker.check(sample);
    flagged += sample.suspect ? 1 : 0;
  }
  EXPECT_EQ(flagged, 0);
}

}  // namespace
}  // namespace rangekit
