#include "rangekit/ls5/formulas.hpp"

namespace rangekit::ls5 {

// §8.8, L11: 25000 is a zero derivative; the difference is held to the code range.
std::uint16_t derivative_code(std::uint16_t current, std::uint16_t previous) noexcept {
  const long value = static_cast<long>(derivative_zero_code) + static_cast<long>(current) - static_cast<long>(previous);
  if (value < 0) return 0;
  if (value > max_result_code) return max_result_code;
  return static_cast<std::uint16_t>(value);
}

// §8.4: "10 bits to transmit one byte (start-bit, 8 data bits, stop-bit)".
unsigned bits_per_byte(const ByteFormat& format) noexcept {
  return 1U + 8U + (format.parity == Parity::none ? 0U : 1U) + format.stop_bits;
}

double transmit_time_ms(std::size_t bytes, std::uint32_t baud, const ByteFormat& format) noexcept {
  return static_cast<double>(bytes) * bits_per_byte(format) * 1000.0 / baud;
}

double stream_record_time_ms(std::uint32_t baud, const ByteFormat& format) noexcept {
  return transmit_time_ms(stream_record_bytes, baud, format);
}

double max_stream_rate_hz(std::uint32_t baud, const ByteFormat& format) noexcept {
  return static_cast<double>(baud) / (static_cast<double>(stream_record_bytes) * bits_per_byte(format));
}

std::optional<BaudRateInfo> slowest_baud_for_stream_rate(double rate_hz, const ByteFormat& format,
                                                         const FirmwareVersion& firmware) noexcept {
  for (const BaudRateInfo& rate : baud_rate_table()) {  // ascending
    if (firmware.at_least(rate.since) && max_stream_rate_hz(rate.baud, format) >= rate_hz) return rate;
  }
  return std::nullopt;
}

double output_period_ms(std::uint16_t period_code, std::uint8_t thinning) noexcept {
  return thinning * period_ms(period_code);
}

}  // namespace rangekit::ls5
