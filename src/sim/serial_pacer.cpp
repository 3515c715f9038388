#include "rangekit/sim/serial_pacer.hpp"

#include <limits>

namespace rangekit {

SerialPacer::SerialPacer(std::uint32_t baud, std::uint32_t hundredths_of_bits_per_char)
    : baud_(baud), hundredths_of_bits_(hundredths_of_bits_per_char) {}

void SerialPacer::reconfigure(std::uint32_t baud, std::uint32_t hundredths_of_bits_per_char, Nanos now) {
  // Bytes still queued go out at the new speed from now on.
  std::vector<std::uint8_t> ignored;
  take_sent(now, ignored);
  baud_ = baud;
  hundredths_of_bits_ = hundredths_of_bits_per_char;
  busy_since_ = now;
  sent_in_period_ = 0;
}

Nanos SerialPacer::completion_of(std::uint64_t index) const {
  // (index + 1) characters of tenths_of_bits/10 bits each at baud bits/s, in ns.
  // Split (index + 1) = q * baud + r so the products stay within 64 bits, exactly.
  const std::uint64_t per_char = static_cast<std::uint64_t>(hundredths_of_bits_) * 10'000'000ULL;  // ns * baud
  const std::uint64_t q = (index + 1) / baud_;
  const std::uint64_t r = (index + 1) % baud_;
  return busy_since_ + Nanos(static_cast<std::int64_t>(q * per_char + r * per_char / baud_));
}

Nanos SerialPacer::character_time() const {
  return Nanos(static_cast<std::int64_t>(hundredths_of_bits_) * 10'000'000LL / baud_);
}

void SerialPacer::send(Bytes bytes, Nanos now) {
  if (bytes.empty()) return;
  if (queue_.empty()) {
    // Idle line: a new busy period starts now (or when the last byte finished, if later).
    const Nanos finished = sent_in_period_ == 0 ? busy_since_ : completion_of(sent_in_period_ - 1);
    busy_since_ = now > finished ? now : finished;
    sent_in_period_ = 0;
  }
  queue_.insert(queue_.end(), bytes.begin(), bytes.end());
}

std::size_t SerialPacer::take_sent(Nanos now, std::vector<std::uint8_t>& out) {
  std::size_t count = 0;
  while (!queue_.empty() && completion_of(sent_in_period_) <= now) {
    out.push_back(queue_.front());
    queue_.pop_front();
    ++sent_in_period_;
    ++count;
  }
  return count;
}

Nanos SerialPacer::next_completion() const {
  if (queue_.empty()) return Nanos::max();
  return completion_of(sent_in_period_);
}

Nanos SerialPacer::idle_at(Nanos now) const {
  if (queue_.empty()) return now;
  return completion_of(sent_in_period_ + queue_.size() - 1);
}

}  // namespace rangekit
