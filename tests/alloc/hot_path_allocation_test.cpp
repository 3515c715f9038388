// The hot path (framing + decoding a measurement stream) must not touch the heap once
// warmed up. A binary of its own: it links bench/allocation_counter.cpp, which replaces
// the global operator new to count allocations.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "allocation_counter.hpp"
#include "rangekit/core/framer.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/core/stream_queue.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/ls5/reply.hpp"
#include "rangekit/ls5/udp_packet.hpp"
#include "rangekit/uls/family.hpp"
#include "rangekit/uls/measurement.hpp"

namespace rangekit {
namespace {

template <class Decode>
long allocations_while_decoding(ScanFunction scan, const std::string& stream, Decode&& decode, int& decoded) {
  FrameAssembler assembler(scan, 1024);  // allocated here, before counting
  const long before = static_cast<long>(bench::allocation_count());
  FrameAssembler::Event event;
  for (std::size_t offset = 0; offset < stream.size(); offset += 100) {
    assembler.push(as_bytes(std::string_view(stream).substr(offset, 100)));
    while (assembler.next(event)) {
      if (event.kind == FrameAssembler::Event::Kind::frame && decode(event.frame)) ++decoded;
    }
  }
  return static_cast<long>(bench::allocation_count()) - before;
}

TEST(HotPathAllocation, CounterSeesAnAllocation) {
  // The instrument works: a string too long for the small-string buffer allocates.
  const long before = static_cast<long>(bench::allocation_count());
  std::string text(100, 'x');
  EXPECT_GT(static_cast<long>(bench::allocation_count()) - before, 0);
  EXPECT_EQ(text.size(), 100U);
}

TEST(HotPathAllocation, UlsMeasurementStreams) {
  // Lines in the formats of §8/§9 (averaging range+pulse width, binning, look down).
  std::string averaging;
  std::string binning;
  for (int i = 0; i < 200; ++i) {
    averaging += "$BM,12." + std::to_string(100 + i) + ",8" + std::to_string(100 + i) + "\r";
    binning += "$BM,0,2,4.572,42\r$BM,1,2,1234.567,7\r";
  }
  int decoded = 0;
  const uls::MeasurementContext both{uls::Mode::averaging, uls::DisplayMode::range_and_intensity, uls::Units::metres,
                                     false};
  EXPECT_EQ(
      allocations_while_decoding(
          &uls::scan_frame, averaging, [&](Bytes frame) { return uls::decode_measurement(frame, both).ok(); }, decoded),
      0);
  EXPECT_EQ(decoded, 200);
  decoded = 0;
  const uls::MeasurementContext bins{uls::Mode::binning, uls::DisplayMode::range, uls::Units::metres, false};
  EXPECT_EQ(
      allocations_while_decoding(
          &uls::scan_frame, binning, [&](Bytes frame) { return uls::decode_measurement(frame, bins).ok(); }, decoded),
      0);
  EXPECT_EQ(decoded, 400);
}

TEST(HotPathAllocation, Ls5StreamRecordsAndUdpPackets) {
  std::string stream;
  for (int i = 0; i < 500; ++i) stream += "!2" + std::to_string(1000 + i * 7 % 9000) + "\r";
  int decoded = 0;
  EXPECT_EQ(allocations_while_decoding(
                &ls5::scan_reply_frame, stream, [&](Bytes frame) { return ls5::parse_reply(frame).ok(); }, decoded),
            0);
  EXPECT_EQ(decoded, 500);

  ls5::UdpPacket packet;
  for (std::size_t i = 0; i < packet.records.size(); ++i)
    packet.records[i] = ls5::UdpRecord{static_cast<std::uint16_t>(i * 50), 0x07};
  std::array<std::uint8_t, ls5::udp_packet_size> datagram{};
  ASSERT_TRUE(ls5::encode_udp_packet(packet, datagram));
  const long before = static_cast<long>(bench::allocation_count());
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(ls5::decode_udp_packet(datagram));
  EXPECT_EQ(static_cast<long>(bench::allocation_count()) - before, 0);
}

// The live path's hand-off, with no allocation per record on the live path
// (docs/performance.md): once both sides' vectors have grown to a batch, a reader pushing
// samples and a consumer taking them in batches allocate nothing more.
TEST(HotPathAllocation, StreamQueueHandOffOfSamplesInBatches) {
  StreamQueue<StreamItem> queue;
  std::vector<StreamItem> batch;
  Sample sample;
  sample.device = "ls5";
  sample.source = "/dev/pts/3";  // a port name as the driver gives it (short: no heap)
  sample.kind = ls5::kind::result;
  sample.set(ls5::channel::code, 1234);
  auto run_batches = [&](int batches) {
    std::size_t taken = 0;
    for (int b = 0; b < batches; ++b) {
      for (int i = 0; i < 3; ++i) queue.push(StreamItem{sample});
      if (queue.take_all(batch, std::chrono::milliseconds(0))) taken += batch.size();
    }
    return taken;
  };
  EXPECT_EQ(run_batches(4), 12U);  // warm-up: the two vectors get their storage
  const long before = static_cast<long>(bench::allocation_count());
  EXPECT_EQ(run_batches(1000), 3000U);
  EXPECT_EQ(static_cast<long>(bench::allocation_count()) - before, 0);
}

// Every record of a stream carries the port it came from, and a real port path
// (/dev/serial/by-id/...) or a scratch pty link is longer than std::string's inline
// buffer: as a std::string, each copy of a Sample would allocate. The name is shared
// instead, so the live path allocates nothing per record.
TEST(HotPathAllocation, CopyingASampleWithALongSourceDoesNotAllocate) {
  const std::string path = "/dev/serial/by-id/usb-FTDI_FT232R_USB_UART_A10KZ3Q7-if00-port0";
  Sample sample;
  sample.device = "ls5";
  sample.source = path;
  sample.kind = ls5::kind::result;
  sample.set(ls5::channel::code, 1234);
  const long before = static_cast<long>(bench::allocation_count());
  Sample copy = sample;
  Sample moved = std::move(copy);
  Sample assigned;
  assigned = moved;
  const bool same = assigned == sample && assigned.source == path && assigned.source == sample.source;
  EXPECT_EQ(static_cast<long>(bench::allocation_count()) - before, 0);
  EXPECT_TRUE(same);
  EXPECT_EQ(assigned.source.str(), path);  // the text itself, unchanged for every output
  EXPECT_EQ(sample.source.view(), path);
}

TEST(HotPathAllocation, SourcesCompareByTheirText) {
  // Two names made apart from the same text are equal; a different text is not.
  const SharedName first = std::string("/dev/serial/by-id/usb-FTDI_FT232R_USB_UART_A10KZ3Q7-if00-port0");
  const SharedName second = std::string("/dev/serial/by-id/usb-FTDI_FT232R_USB_UART_A10KZ3Q7-if00-port0");
  const SharedName other = std::string("/dev/serial/by-id/usb-FTDI_FT232R_USB_UART_B20KZ3Q7-if00-port0");
  EXPECT_EQ(first, second);
  EXPECT_NE(first, other);
  EXPECT_LT(first, other);
  EXPECT_TRUE(SharedName().empty());
  EXPECT_EQ(SharedName(), "");
  EXPECT_EQ(SharedName("").str(), "");
}

// A binning burst: §9 "Up to 15 targets maximum or 15 lines maximum per measurement"
// (and §3 "The maximum number of targets allowed in Binning Mode is 15"). The targets
// are kept in the sample, so copying a full burst does not allocate either.
TEST(HotPathAllocation, CopyingABinningSampleOfFifteenTargetsDoesNotAllocate) {
  Sample burst;
  burst.device = "uls";
  burst.source = "/dev/serial/by-id/usb-FTDI_FT232R_USB_UART_A10KZ3Q7-if00-port0";
  burst.kind = uls::kind::binning;
  std::vector<TargetHit> collected;
  for (std::uint32_t i = 0; i < 15; ++i) collected.push_back(TargetHit{1.0 + 0.75 * i, 100 + i});
  const long before = static_cast<long>(bench::allocation_count());
  burst.targets.assign(collected.begin(), collected.end());
  Sample copy = burst;
  StreamItem item{std::move(copy)};
  const Sample& queued = std::get<Sample>(item);
  const bool same = queued == burst;
  EXPECT_EQ(static_cast<long>(bench::allocation_count()) - before, 0);
  EXPECT_TRUE(same);
  ASSERT_EQ(queued.targets.size(), 15U);
  EXPECT_DOUBLE_EQ(queued.targets[14].distance_m, 11.5);
  EXPECT_EQ(queued.targets[14].strength, 114U);
}

TEST(HotPathAllocation, MoreThanFifteenTargetsStillFit) {
  // A capture written by hand may hold more than the ULS reports: none is lost.
  TargetList targets;
  for (std::uint32_t i = 0; i < 20; ++i) targets.push_back(TargetHit{0.5 * i, i});
  ASSERT_EQ(targets.size(), 20U);
  for (std::uint32_t i = 0; i < 20; ++i) {
    EXPECT_DOUBLE_EQ(targets[i].distance_m, 0.5 * i);
    EXPECT_EQ(targets[i].strength, i);
  }
  const TargetList copy = targets;
  EXPECT_EQ(copy, targets);
  targets.clear();
  EXPECT_TRUE(targets.empty());
  targets = {{4.572, 42}, {7.1, 13}};
  ASSERT_EQ(targets.size(), 2U);
  EXPECT_EQ(targets.back().strength, 13U);
  EXPECT_NE(copy, targets);
}

}  // namespace
}  // namespace rangekit
