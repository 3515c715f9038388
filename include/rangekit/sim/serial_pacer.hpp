// A UART transmitter model: bytes leave one at a time, each taking the line's
// character time, so output rates limited by the baud rate emerge from pacing
// (ULS section 9, LS5 section 8.4) rather than from a table.
//
// Completion times are computed from the start of a busy period as
// start + k * bit_time_numerator / baud, in integer nanoseconds, so a long run
// accumulates no rounding drift.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include "rangekit/core/framer.hpp"
#include "rangekit/sim/clock.hpp"

namespace rangekit {

class SerialPacer {
 public:
  // `hundredths_of_bits_per_char`: 100 for 10-bit 8N1 bytes; 115.2 bit times (ULS,
  // docs/conformance.md U19) is 1152.
  SerialPacer(std::uint32_t baud, std::uint32_t hundredths_of_bits_per_char);

  void reconfigure(std::uint32_t baud, std::uint32_t hundredths_of_bits_per_char, Nanos now);
  // Queues bytes for sending; transmission starts at `now` if the line is idle.
  void send(Bytes bytes, Nanos now);
  // Appends to `out` every byte whose last bit has left the line by `now`.
  std::size_t take_sent(Nanos now, std::vector<std::uint8_t>& out);
  // When the next queued byte will have left the line (Nanos::max() if none).
  [[nodiscard]] Nanos next_completion() const;
  // When the line will be idle again (now, if it is already).
  [[nodiscard]] Nanos idle_at(Nanos now) const;
  [[nodiscard]] std::size_t queued() const noexcept { return queue_.size(); }
  [[nodiscard]] Nanos character_time() const;
  void clear() noexcept { queue_.clear(); }

 private:
  [[nodiscard]] Nanos completion_of(std::uint64_t index) const;

  std::uint32_t baud_;
  std::uint32_t hundredths_of_bits_;
  std::deque<std::uint8_t> queue_;
  Nanos busy_since_{0};               // start of the current busy period
  std::uint64_t sent_in_period_ = 0;  // bytes completed since busy_since_
};

}  // namespace rangekit
