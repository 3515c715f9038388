#include "rangekit/ls5/commands.hpp"

#include <array>

namespace rangekit::ls5 {
namespace {

using R = RequestForm;
using S = ResponseForm;

// Table 9.1, row by row. Notes 1 and 2 mark the same rows: the commands that only
// echo may be broadcast, and a broadcast is never answered.
constexpr std::array<CommandInfo, command_count> commands{{
    {CommandId::identification, "ID", "Identification", "identify", R::no_argument, S::identification, false, false},
    {CommandId::read_parameter, "R", "Read the parameter", "read", R::parameter_address, S::parameter_value, false,
     false},
    {CommandId::write_parameter, "W", "Write the parameter", "write", R::address_and_value, S::echo, true, true},
    {CommandId::store_to_flash, "FL", "Save parameters to non-volatile memory (Store current parameters to FLASH)",
     "store", R::no_argument, S::echo, true, true},
    {CommandId::turn_on, "ON", "Turn on the sensor", "turn-on", R::no_argument, S::echo, true, true},
    {CommandId::turn_off, "OF", "Turn off the sensor", "turn-off", R::no_argument, S::echo, true, true},
    {CommandId::latch_result, "FX", "Latch the result", "latch", R::no_argument, S::echo, true, true},
    {CommandId::start_stream, "ST", "Start the result stream", "start-stream", R::no_argument, S::stream, false, false},
    {CommandId::stop_stream, "SB", "Stop the stream", "stop-stream", R::no_argument, S::echo, true, true},
    {CommandId::read_latched, "FR", "Read the latched result", "read-latched", R::no_argument, S::result, false, false},
    {CommandId::read_last, "LR", "Read the last result", "read-last", R::no_argument, S::result, false, false},
    {CommandId::restore_defaults, "DF", "Restoring default parameters", "restore-defaults", R::no_argument, S::echo,
     true, true},
}};

// The table is indexed by CommandId; keep them in step.
constexpr bool table_in_enum_order() {
  for (std::size_t i = 0; i < commands.size(); ++i) {
    if (static_cast<std::size_t>(commands[i].id) != i) return false;
  }
  return true;
}
static_assert(table_in_enum_order(), "command table rows must follow CommandId order");

}  // namespace

std::span<const CommandInfo> command_table() noexcept { return commands; }

const CommandInfo& command_info(CommandId id) noexcept {
  const auto index = static_cast<std::size_t>(id);
  return commands[index < commands.size() ? index : 0];
}

const CommandInfo* find_command_by_code(std::string_view code) noexcept {
  for (const CommandInfo& command : commands) {
    if (command.code == code) return &command;
  }
  return nullptr;
}

const CommandInfo* find_command_by_cli_name(std::string_view cli_name) noexcept {
  for (const CommandInfo& command : commands) {
    if (command.cli_name == cli_name) return &command;
  }
  return nullptr;
}

std::size_t request_argument_length(RequestForm form) noexcept {
  switch (form) {
    case RequestForm::no_argument:
      return 0;
    case RequestForm::parameter_address:
      return 2;
    case RequestForm::address_and_value:
      return 4;
  }
  return 0;
}

std::size_t reply_argument_length(const CommandInfo& command) noexcept {
  switch (command.response) {
    case ResponseForm::echo:
      return request_argument_length(command.request);
    case ResponseForm::parameter_value:
      return 4;
    case ResponseForm::result:
      return 5;
    case ResponseForm::identification:
      return 35;
    case ResponseForm::stream:
      return 0;
  }
  return 0;
}

}  // namespace rangekit::ls5
