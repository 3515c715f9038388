// L78: the real-clock loop runs the firmware when next_wake() asks, not at every byte:
// a streamed record is run and handed over in one wake, once its <cr> has left.
#include <gtest/gtest.h>

#include <vector>

#include "ls5_emulator/firmware_rig.hpp"

namespace rangekit::ls5::emulator::testing {
namespace {

// §8.4: "When the stream is running, data is sent to the sensor output with a period
// T=n×t" and "the data packet contains 7 bytes when the stream is running ... it requires
// 10 bits to transmit one byte ... 7·10·1/115200 = 0.61 ms".
TEST(Ls5LoopWake, L78_OneWakePerStreamRecordAfterItsCrAtTheStreamPeriod) {
  Rig rig;
  rig.write(0x06, 0x0A);
  rig.write(0x07, 0x00);  // t = 1 ms, n = 1
  rig.send("#01ST\r");
  rig.run_for(10ms);
  rig.out.clear();
  rig.bytes.clear();

  // The runtime's loop, woken only at next_wake().
  std::vector<Nanos> record_ends;
  int wakes = 0;
  const Nanos until = rig.now + 100ms;
  while (rig.fw->next_wake() <= until) {
    const Nanos wake = rig.fw->next_wake();
    ASSERT_GT(wake, rig.now) << "next_wake() did not move past the last wake";
    rig.now = wake;
    rig.fw->advance(rig.now);
    const std::size_t before = rig.out.size();
    rig.collect();
    ++wakes;
    // Whole records only: 7 bytes ending in <cr>, the <cr> done at most 7 ns before the wake.
    const std::size_t handed = rig.out.size() - before;
    ASSERT_EQ(handed, 7U) << "wake " << wakes;
    ASSERT_EQ(rig.out.back(), '\r');
    EXPECT_LE(rig.bytes.back().done, wake);
    EXPECT_LE(wake - rig.bytes.back().done, Nanos(7));
    record_ends.push_back(rig.bytes.back().done);
  }
  EXPECT_EQ(wakes, 100);  // one per record over 100 ms at T = 1 ms
  for (std::size_t i = 1; i < record_ends.size(); ++i) EXPECT_EQ(record_ends[i] - record_ends[i - 1], 1ms);
  EXPECT_EQ(rig.fw->records_skipped(), 0U);
}

}  // namespace
}  // namespace rangekit::ls5::emulator::testing
