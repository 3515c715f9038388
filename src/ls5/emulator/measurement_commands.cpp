// The LS5 model's commands on measuring (ON, OF), its results (FX, FR, LR) and the
// result stream (ST, SB), table 9.1.
#include "rangekit/ls5/emulator/firmware.hpp"

#include "ls5/emulator/command_handlers.hpp"

namespace rangekit::ls5::emulator {

void Firmware::handle_turn_on(const Exchange& exchange) {
  if (!on_) {
    on_ = true;
    if (phase_ == Phase::operating && ram_[address::triggering] == 0) next_measurement_ = exchange.now + period();
  }
  echo(exchange);
}

void Firmware::handle_turn_off(const Exchange& exchange) {
  on_ = false;
  next_measurement_ = Nanos::max();
  update_outputs();  // §8.2: discrete outputs 0, analog holds
  echo(exchange);
}

void Firmware::handle_latch_result(const Exchange& exchange) {
  latch(exchange.now);
  echo(exchange);
}

void Firmware::handle_start_stream(const Exchange&) {
  streaming_ = true;
  thinning_count_ = 0;  // no echo (L24)
}

void Firmware::handle_stop_stream(const Exchange& exchange) {
  streaming_ = false;
  echo(exchange);
}

void Firmware::handle_read_latched(const Exchange& exchange) {
  reply(Reply::result_of(exchange.own, CommandId::read_latched, latched_), exchange.now);
}

void Firmware::handle_read_last(const Exchange& exchange) {
  reply(Reply::result_of(exchange.own, CommandId::read_last, current_), exchange.now);
}

}  // namespace rangekit::ls5::emulator
