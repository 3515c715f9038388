// The hot path (framing + decoding a measurement stream) must not touch the
// heap once warmed up (issue 3). This binary links bench/allocation_counter.cpp,
// which replaces the global operator new to count allocations: that is why it
// is a test binary of its own.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "rangekit/core/framer.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/core/stream_queue.hpp"
#include "rangekit/ls5/reply.hpp"
#include "rangekit/ls5/udp_packet.hpp"
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

// The live path's hand-off (issue 17 item 2: "no allocation per record on the live
// path"): once both sides' vectors have grown to a batch, a reader pushing samples and a
// consumer taking them in batches allocate nothing more. (A deque allocated a node for
// every item or two of a StreamItem's size.)
TEST(HotPathAllocation, StreamQueueHandOffOfSamplesInBatches) {
  StreamQueue<StreamItem> queue;
  std::vector<StreamItem> batch;
  Sample sample;
  sample.device = "ls5";
  sample.source = "/dev/pts/3";  // a port name as the driver gives it (short: no heap)
  sample.kind = SampleKind::ls5_result;
  sample.code = 1234;
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

}  // namespace
}  // namespace rangekit
