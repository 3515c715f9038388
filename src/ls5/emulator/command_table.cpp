// The LS5 model's table 9.1 commands: one handler per command id, and the echo most of
// them answer with.
#include "rangekit/ls5/emulator/firmware.hpp"

#include <array>
#include <cstddef>

#include "ls5/emulator/command_handlers.hpp"
#include "rangekit/sim/handler_table.hpp"

namespace rangekit::ls5::emulator {

Firmware::CommandHandler Firmware::handler(CommandId id) noexcept {
  using Id = CommandId;
  // In CommandId's order, as the codec's table: a row is found by its id.
  static constexpr std::array<sim::HandlerRow<CommandId, CommandHandler>, command_count> rows{{
      {Id::identification, &Firmware::handle_identification},
      {Id::read_parameter, &Firmware::handle_read_parameter},
      {Id::write_parameter, &Firmware::handle_write_parameter},
      {Id::store_to_flash, &Firmware::handle_store_to_flash},
      {Id::turn_on, &Firmware::handle_turn_on},
      {Id::turn_off, &Firmware::handle_turn_off},
      {Id::latch_result, &Firmware::handle_latch_result},
      {Id::start_stream, &Firmware::handle_start_stream},
      {Id::stop_stream, &Firmware::handle_stop_stream},
      {Id::read_latched, &Firmware::handle_read_latched},
      {Id::read_last, &Firmware::handle_read_last},
      {Id::restore_defaults, &Firmware::handle_restore_defaults},
  }};
  static_assert(sim::in_id_order(rows), "LS5 handler rows out of CommandId order");
  return rows[static_cast<std::size_t>(id)].handle;
}

void Firmware::echo(const Exchange& exchange) {
  if (exchange.answer) reply(Reply::echo(exchange.request), exchange.now);
}

}  // namespace rangekit::ls5::emulator
