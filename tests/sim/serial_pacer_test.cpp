// Byte pacing on a virtual clock: rates emerge from character times.
#include <gtest/gtest.h>

#include "rangekit/sim/serial_pacer.hpp"

namespace rangekit {
namespace {

using namespace std::chrono_literals;

TEST(SerialPacer, TenBitBytesAt115200) {
  SerialPacer pacer(115200, 1000);
  EXPECT_EQ(pacer.character_time(), Nanos(86805));  // 10 / 115200 s
  pacer.send(as_bytes("!25000\r"), 0ns);
  std::vector<std::uint8_t> out;
  EXPECT_EQ(pacer.take_sent(Nanos(86804), out), 0U);
  EXPECT_EQ(pacer.take_sent(Nanos(86805), out), 1U);
  // LS5 section 8.4: 7 bytes at 115200 8N1 take 7*10/115200 = 0.61 ms.
  EXPECT_EQ(pacer.idle_at(0ns), Nanos(607638));
  EXPECT_EQ(pacer.take_sent(1ms, out), 6U);
  EXPECT_EQ(std::string(out.begin(), out.end()), "!25000\r");
}

TEST(SerialPacer, UlsCharacterTimeIs100MicrosecondsAt115200) {
  SerialPacer pacer(115200, 1152);  // docs/conformance.md U19
  EXPECT_EQ(pacer.character_time(), 100us);
  pacer.send(as_bytes("$BM,1234.567\r"), 0ns);  // 13 bytes
  EXPECT_EQ(pacer.idle_at(0ns), 1300us);
}

TEST(SerialPacer, NoDriftOverAMillionBytes) {
  SerialPacer pacer(921600, 1000);
  std::vector<std::uint8_t> out;
  const std::vector<std::uint8_t> block(1000, 0x55);
  for (int i = 0; i < 1000; ++i) pacer.send(block, 0ns);
  // 1,000,000 bytes * 10 bits / 921600 baud = 10.850694444 s
  EXPECT_EQ(pacer.idle_at(0ns), Nanos(10'850'694'444));
  EXPECT_EQ(pacer.take_sent(Nanos(10'850'694'444), out), 1'000'000U);
}

TEST(SerialPacer, IdleLineStartsANewPeriodWhenBytesArrive) {
  SerialPacer pacer(9600, 1000);
  std::vector<std::uint8_t> out;
  pacer.send(as_bytes("A"), 0ns);
  EXPECT_EQ(pacer.take_sent(1s, out), 1U);
  pacer.send(as_bytes("B"), 5s);
  EXPECT_EQ(pacer.next_completion(), 5s + Nanos(1'041'666));
  EXPECT_EQ(pacer.take_sent(5s + Nanos(1'041'665), out), 0U);
  EXPECT_EQ(pacer.take_sent(6s, out), 1U);
}

TEST(SerialPacer, BytesQueuedWhileBusyFollowBackToBack) {
  SerialPacer pacer(115200, 1000);
  pacer.send(as_bytes("AB"), 0ns);
  pacer.send(as_bytes("C"), Nanos(10));  // line still busy: no gap
  EXPECT_EQ(pacer.idle_at(Nanos(10)), Nanos(260416));
}

TEST(SerialPacer, BaudChangeAppliesToBytesStillQueued) {
  SerialPacer pacer(115200, 1000);
  std::vector<std::uint8_t> out;
  pacer.send(as_bytes("ABCD"), 0ns);
  pacer.take_sent(Nanos(86805), out);  // 'A' gone
  pacer.reconfigure(57600, 1000, Nanos(86805));
  EXPECT_EQ(pacer.next_completion(), Nanos(86805 + 173611));
}

}  // namespace
}  // namespace rangekit
