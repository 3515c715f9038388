// What a result drives: the analog output (§8.10), the discrete outputs (§8.11), latching
// with recalculation (§8.14) and the Ethernet packets (§10.1).
#include "rangekit/ls5/emulator/firmware.hpp"

#include <array>
#include <cmath>

namespace rangekit::ls5::emulator {

void Firmware::update_outputs() {
  if (!on_) {
    oc1_ = oc2_ = false;  // §8.2; the analog output keeps its last state
    return;
  }
  // §8.10: "If the analog output is disabled, its value remains the same as it was at the last
  // measurement before the output was disabled" (L53).
  if (ram_[address::analog_enabled] == 0x01) {
    analog_ =
        analog_output(config_.analog, AnalogLimits{u16(address::analog_lower_low), u16(address::analog_upper_low)},
                      current_, last_result_code_);
  }
  if (current_.is_result()) last_result_code_ = current_.value;
  const auto outputs = decode_discrete_outputs(ram_[address::discrete_outputs]);
  if (!outputs) return;
  oc1_ = discrete_output_state(outputs->output1,
                               Swings{u16(address::output1_first_swing_low), u16(address::output1_second_swing_low)},
                               current_.value);
  oc2_ = discrete_output_state(outputs->output2,
                               Swings{u16(address::output2_first_swing_low), u16(address::output2_second_swing_low)},
                               current_.value);
  oc1_ = oc1_ && config_.discrete_outputs >= 1;
  oc2_ = oc2_ && config_.discrete_outputs >= 2;
}

void Firmware::latch(Nanos) {
  latched_ = current_;
  auto recalculation = recalculate_on_latch(ram_[address::latching], latched_, u16(address::analog_fixed_range_low),
                                            u16(address::discrete_fixed_range_low));
  if (!recalculation || !recalculation->recalculated) return;
  for (const auto& write : recalculation->writes.view()) {
    ram_[write.address] = write.value;
    (void)take_byte_of_number(write.address, true);  // both bytes of each limit: no pair left half written
  }
  if (recalculation->to_rom) {
    if (!rom_) rom_ = delivered_rom();
    for (const auto& write : recalculation->writes.view()) (*rom_)[write.address] = write.value;
    (void)save_rom();
  }
  update_outputs();
}

void Firmware::push_udp(const ResultCode& code) {
  UdpRecord record;
  record.state = static_cast<std::uint8_t>(udp_state::always_one | udp_state::measured);
  if (code.is_result()) {
    record.code = static_cast<std::uint16_t>(
        std::llround(code.value * static_cast<double>(udp_full_scale_code) / static_cast<double>(max_result_code)));
    record.state = static_cast<std::uint8_t>(record.state | udp_state::in_range);
  }
  if (version_.at_least(firmware_8_0) && ram_[address::result_type] == 0x01) {
    record.state = static_cast<std::uint8_t>(record.state | udp_state::derivative);
  }
  udp_packet_.records[udp_fill_++] = record;
  if (udp_fill_ < udp_record_count) return;
  udp_fill_ = 0;
  udp_packet_.serial_number = static_cast<std::uint16_t>(config_.serial_number & 0xFFFF);
  udp_packet_.lower_boundary_mm = static_cast<std::uint16_t>(std::llround(config_.lower_boundary_mm));
  udp_packet_.range_mm = static_cast<std::uint16_t>(std::llround(config_.range_mm));
  udp_packet_.counter = udp_counter_++;
  UdpDatagram datagram;
  if (!encode_udp_packet(udp_packet_, datagram.bytes)) return;
  ++udp_packets_;
  if (!config_.udp_sink) return;
  // Read at each packet, so a write to 6E/6F or 5C-5F/6C/6D (or DF) moves the next packet (L82, L93).
  datagram.source_port = udp_source_port();
  const UdpDestination destination = udp_destination();
  datagram.destination_ip = destination.ip;
  datagram.destination_port = destination.port;
  if (auto sent = config_.udp_sink(datagram); !sent) {
    ++udp_unsent_;
    udp_error_ = sent.error().message;
  } else {
    udp_error_.clear();
  }
}

std::uint16_t Firmware::udp_source_port() const noexcept { return number(LogicalValueId::source_port); }

UdpDestination Firmware::udp_destination() const noexcept {
  std::uint32_t ip = 0;
  for (std::uint8_t i = 0; i < 4; ++i) {
    ip = ip << 8U | ram_[static_cast<std::uint8_t>(address::destination_ip_first + i)];
  }
  return UdpDestination{ip, number(LogicalValueId::destination_port)};
}

}  // namespace rangekit::ls5::emulator
