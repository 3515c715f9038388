// The LS5 model's table 9.2 parameters in RAM: R reads one, W writes one byte, DF puts the
// defaults back; each W acts at once on what the byte drives.
#include "rangekit/ls5/emulator/firmware.hpp"

#include "ls5/emulator/command_handlers.hpp"

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
  // L50: nor when the number the byte is part of would leave its range (limits above 50000, period 0, ...).
  const auto ram_byte = [this](std::uint8_t at) { return ram_[at]; };
  if (!check_value_after_write(request.parameter, request.value, ram_byte)) return;
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

void Firmware::handle_restore_defaults(const Exchange& exchange) {
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
