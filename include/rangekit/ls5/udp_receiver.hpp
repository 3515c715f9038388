// The LS5 Ethernet stream (§10.1) as a SampleSource: 512-byte UDP packets of 168
// records on a bound socket, checksum checked (a bad packet is counted and
// reported as a bad_frame event; a bad record is a suspect sample, its packet
// kept), the cyclic counter followed (a gap is reported
// as a lost_records event with the number of records lost, never merged over; a
// repeated counter is a duplicated datagram, dropped, counted and reported).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/core/udp.hpp"
#include "rangekit/ls5/udp_packet_reader.hpp"

namespace rangekit::ls5 {

struct UdpReceiverOptions {
  std::size_t queue_capacity = 65536;
  int address = -1;  // the sensor's network address if known (Samples carry it)
};

using UdpReceiverCounters = UdpPacketCounters;

class UdpReceiver final : public SampleSource {
 public:
  // Binds `local` (the user's HOST:PORT; port 0 picks one) and starts the reader thread.
  static Result<std::unique_ptr<UdpReceiver>> start(const Endpoint& local, UdpReceiverOptions options = {});
  ~UdpReceiver() override;

  std::optional<StreamItem> next(std::chrono::milliseconds timeout) override;
  bool next_batch(std::vector<StreamItem>& batch, std::chrono::milliseconds timeout) override;
  [[nodiscard]] bool finished() const override;
  void stop() override;
  // Records lost to counter gaps plus records the queue dropped.
  [[nodiscard]] std::uint64_t lost() const override;

  [[nodiscard]] Endpoint local_endpoint() const;
  [[nodiscard]] UdpReceiverCounters counters() const;

 private:
  struct State;
  explicit UdpReceiver(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace rangekit::ls5
