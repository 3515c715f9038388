// The LS5 model's UART (§8.3, §9.1): the stored baud and byte format, requests framed from
// the bytes received, replies paced at the line's speed.
#include "rangekit/ls5/emulator/firmware.hpp"

#include <algorithm>
#include <cstddef>

namespace rangekit::ls5::emulator {
namespace {

using namespace std::chrono_literals;

rangekit::SerialSettings settings_from(std::uint32_t baud, const ByteFormat& format) {
  rangekit::SerialSettings settings;
  settings.baud = baud;
  settings.parity = format.parity == Parity::none   ? rangekit::Parity::none
                    : format.parity == Parity::even ? rangekit::Parity::even
                                                    : rangekit::Parity::odd;
  settings.stop_bits = format.stop_bits;
  return settings;
}

}  // namespace

rangekit::SerialSettings Firmware::stored_serial_settings() const {
  const auto baud = baud_rate_from_code(ram_[address::baud_rate]).value_or(115200);
  const auto format = byte_format_from_code(ram_[address::byte_format]).value_or(ByteFormat{0, Parity::none, 1, "8N1"});
  return settings_from(baud, format);
}

std::uint32_t Firmware::bits_hundredths(const rangekit::SerialSettings& settings) const {
  return static_cast<std::uint32_t>(settings.bits_per_byte()) * 100U;
}

void Firmware::apply_serial(const rangekit::SerialSettings& settings, Nanos now) {
  drain_pacer(now);
  pacer_.reconfigure(settings.baud, bits_hundredths(settings), now);
  serial_ = settings;
}

void Firmware::apply_serial_after_reply(Nanos now) {
  pending_serial_ = stored_serial_settings();
  pending_serial_at_ = pacer_.idle_at(now) + 1ns;
}

rangekit::SerialSettings Firmware::port_settings(std::size_t) const { return serial_; }

void Firmware::receive(std::size_t, std::uint8_t byte, Nanos now) {
  last_now_ = std::max(last_now_, now);
  if (phase_ == Phase::initializing) return;  // §8.2: the UART is not set up yet
  // §9.2: the stream stops when the sensor gets at least one correct byte.
  streaming_ = false;
  rx_.push_back(byte);
  while (!rx_.empty()) {
    const FrameScan scan = scan_request_frame(Bytes(rx_.data(), rx_.size()));
    if (scan.status == FrameStatus::need_more) break;
    if (scan.status == FrameStatus::complete) {
      const std::vector<std::uint8_t> frame(scan.frame.begin(), scan.frame.end());
      rx_.erase(rx_.begin(), rx_.begin() + static_cast<std::ptrdiff_t>(scan.consumed));
      handle_frame(Bytes(frame.data(), frame.size()), now);
      continue;
    }
    rx_.erase(rx_.begin(), rx_.begin() + static_cast<std::ptrdiff_t>(std::max<std::size_t>(1, scan.consumed)));
  }
}

void Firmware::reply(const Reply& answer, Nanos now) {
  auto text = encode_reply(answer);
  if (!text) return;
  pacer_.send(text->bytes(), now);
}

void Firmware::drain_pacer(Nanos now) {
  std::vector<std::uint8_t> bytes;
  while (pacer_.next_completion() <= now) {
    const Nanos done = pacer_.next_completion();
    bytes.clear();
    pacer_.take_sent(done, bytes);
    // Stamped with the settings they leave with: a W to 04/05 changes them right
    // after its echo has gone (L28), before the runtime hands the echo to the host.
    for (const auto value : bytes) {
      sent_.push_back(LineByte{done, value, serial_.baud, static_cast<std::uint8_t>(serial_.stop_bits)});
    }
  }
}

void Firmware::take_line_output(std::size_t, Nanos now, std::vector<LineByte>& out) {
  drain_pacer(now);
  std::size_t taken = 0;
  while (taken < sent_.size() && sent_[taken].done <= now) out.push_back(sent_[taken++]);
  sent_.erase(sent_.begin(), sent_.begin() + static_cast<std::ptrdiff_t>(taken));
}

}  // namespace rangekit::ls5::emulator
