// The LS5 model's table 9.2 parameters in RAM: R reads one, W writes one byte, DF puts the
// defaults back; each W acts at once on what the byte drives.
#include "rangekit/ls5/emulator/firmware.hpp"

#include "ls5/emulator/command_handlers.hpp"
#include "rangekit/ls5/logical_values.hpp"

namespace rangekit::ls5::emulator {

void Firmware::handle_read_parameter(const Exchange& exchange) {
  const Request& request = exchange.request;
  if (!check_parameter_available(request.parameter, model_)) return;  // L25: no reply
  reply(Reply::parameter_value(exchange.own, request.parameter, ram_[request.parameter]), exchange.now);
}

void Firmware::handle_write_parameter(const Exchange& exchange) {
  const Request& request = exchange.request;
  const Nanos now = exchange.now;
  if (!check_parameter_byte(request.parameter, request.value, model_)) return;  // L26: no reply, no change
  // L84: the number a byte is part of is checked on the pair (limits above 50000, period 0, ...).
  const auto ram_byte = [this](std::uint8_t at) { return ram_[at]; };
  const bool in_range = check_value_after_write(request.parameter, request.value, ram_byte).ok();
  if (!take_byte_of_number(request.parameter, in_range)) return;
  ram_[request.parameter] = request.value;
  echo(exchange);
  apply_parameter(request.parameter, now);
}

void Firmware::apply_parameter(std::uint8_t p, Nanos now) {
  if ((p == address::baud_rate || p == address::byte_format) && phase_ == Phase::operating) {
    apply_serial_after_reply(now);
  }
  if (p == address::pre_filter || p == address::averaging_points || p == address::median_points) window_.clear();
  // §8.13: "When triggered by an internal timer, the sensor measures according to the set
  // parameter" period: the timer starts again from the new setting.
  if (p == address::triggering || p == address::period_low || p == address::period_high) {
    if (phase_ == Phase::operating && on_) {
      next_measurement_ = ram_[address::triggering] == 0 ? now + period() : Nanos::max();
    }
  }
}

bool Firmware::take_byte_of_number(std::uint8_t p, bool in_range) {
  const ParameterInfo* parameter = find_parameter(p);
  if (parameter == nullptr || parameter->part_of == LogicalValueId::none) return true;
  const LogicalValueId id = parameter->part_of;
  auto& held = held_[static_cast<std::size_t>(id)];
  if (in_range) {
    if (held) --held_count_;
    held.reset();
    return true;
  }
  // Table 9.3 writes the low byte first: from 50000, 25000's A8 makes C3A8 until 61 follows.
  if (!held) {
    held = HeldNumber{p, ram_number(id)};
    ++held_count_;
    return true;
  }
  if (held->written == p) return true;  // the first byte again, still waiting for the other
  // Both bytes are written and the pair is out of range: refused as a whole, the first undone.
  write_ram_number(id, held->in_effect);
  held.reset();
  --held_count_;
  return false;
}

std::uint16_t Firmware::ram_number(LogicalValueId id) const noexcept {
  std::uint16_t value = 0;
  for (const std::uint8_t at : logical_value_info(id).addresses) {
    value = static_cast<std::uint16_t>(value | ram_[at] << (8U * find_parameter(at)->significance));
  }
  return value;
}

void Firmware::write_ram_number(LogicalValueId id, std::uint16_t value) noexcept {
  for (const std::uint8_t at : logical_value_info(id).addresses) {
    ram_[at] = static_cast<std::uint8_t>(value >> (8U * find_parameter(at)->significance));
  }
}

std::uint16_t Firmware::number(LogicalValueId id) const noexcept {
  if (held_count_ > 0) {
    if (const auto& held = held_[static_cast<std::size_t>(id)]) return held->in_effect;
  }
  return ram_number(id);
}

std::array<std::uint8_t, 256> Firmware::ram_in_effect() const {
  auto memory = ram_;
  for (std::size_t id = 0; id < held_.size(); ++id) {
    if (!held_[id]) continue;
    for (const std::uint8_t at : logical_value_info(static_cast<LogicalValueId>(id)).addresses) {
      memory[at] = static_cast<std::uint8_t>(held_[id]->in_effect >> (8U * find_parameter(at)->significance));
    }
  }
  return memory;
}

void Firmware::release_held_numbers() noexcept {
  held_.fill(std::nullopt);
  held_count_ = 0;
}

void Firmware::handle_restore_defaults(const Exchange& exchange) {
  release_held_numbers();
  const auto before = ram_;
  ram_ = table_defaults();  // RAM only, until FL (L27); network address 01 from the next request (L55)
  echo(exchange);
  // Each default a byte changed to acts at once, as a W of that value would (L83).
  for (std::size_t at = 0; at < ram_.size(); ++at) {
    if (ram_[at] != before[at]) apply_parameter(static_cast<std::uint8_t>(at), exchange.now);
  }
  window_.clear();
}

}  // namespace rangekit::ls5::emulator
