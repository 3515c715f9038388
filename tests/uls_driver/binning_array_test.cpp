// One binning target array is one measurement (U10), whether polled or streamed; both
// paths collect it with collect_binning_target.
#include <gtest/gtest.h>

#include <vector>

#include "uls/driver/binning_array.hpp"

namespace rangekit::uls::detail {
namespace {

BinningTarget line(std::uint8_t index, std::uint8_t count, double metres, std::uint32_t strength) {
  BinningTarget target;
  target.index = index;
  target.count = count;
  target.range = make_range(metres, Units::metres);
  target.strength = strength;
  return target;
}

// §9 "$BM,I,A,XXXX.XXX,SSS": "I = index value in array", "A = number of targets in the array".
TEST(UlsBinningArray, U10_CollectsTheLinesOfOneArrayInOrder) {
  std::vector<TargetHit> targets;
  EXPECT_EQ(collect_binning_target(targets, line(0, 2, 12.5, 40)), BinningArray::incomplete);
  EXPECT_EQ(collect_binning_target(targets, line(1, 2, 30.25, 7)), BinningArray::complete);
  ASSERT_EQ(targets.size(), 2u);
  EXPECT_DOUBLE_EQ(targets[0].distance_m, 12.5);
  EXPECT_EQ(targets[0].strength, 40u);
  EXPECT_DOUBLE_EQ(targets[1].distance_m, 30.25);
  EXPECT_EQ(targets[1].strength, 7u);
  // Index 0 starts the next array.
  EXPECT_EQ(collect_binning_target(targets, line(0, 1, 5.0, 3)), BinningArray::complete);
  ASSERT_EQ(targets.size(), 1u);
  EXPECT_DOUBLE_EQ(targets[0].distance_m, 5.0);
}

TEST(UlsBinningArray, U10_ALineOutOfOrderDropsTheArray) {
  std::vector<TargetHit> targets;
  EXPECT_EQ(collect_binning_target(targets, line(0, 3, 1.0, 9)), BinningArray::incomplete);
  EXPECT_EQ(collect_binning_target(targets, line(2, 3, 3.0, 9)), BinningArray::out_of_order);  // line 1 lost
  EXPECT_TRUE(targets.empty());
  EXPECT_EQ(collect_binning_target(targets, line(1, 3, 2.0, 9)), BinningArray::out_of_order);
}

}  // namespace
}  // namespace rangekit::uls::detail
