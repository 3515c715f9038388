// Table 9.1 of the LS5 manual as data: the twelve commands of the serial protocol.
// The codec, the emulator, the driver, CLI help and docs all read this one table.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace rangekit::ls5 {

enum class CommandId : std::uint8_t {
  identification,    // ID
  read_parameter,    // R
  write_parameter,   // W
  store_to_flash,    // FL
  turn_on,           // ON
  turn_off,          // OF
  latch_result,      // FX
  start_stream,      // ST
  stop_stream,       // SB
  read_latched,      // FR
  read_last,         // LR
  restore_defaults,  // DF
};

inline constexpr std::size_t command_count = 12;

// What follows the command code in a request.
enum class RequestForm : std::uint8_t {
  no_argument,        // #AAON
  parameter_address,  // #AARaa
  address_and_value,  // #AAWaadd
};

// What the sensor sends back (table 9.1 "Response format").
enum class ResponseForm : std::uint8_t {
  echo,             // the request with '!' for '#': !AAON, !AAWaadd
  parameter_value,  // !AARaadd: the address asked for and its value
  identification,   // %AA + 35 characters (§9.2, conformance L2)
  result,           // !AAFRddddd: the command and a 5-digit result code
  stream,           // no reply of its own; records !ddddd follow (conformance L1)
};

struct CommandInfo {
  CommandId id;
  std::string_view code;      // on the wire: "ID", "R", "W", ...
  std::string_view name;      // as table 9.1 names it
  std::string_view cli_name;  // lower-case, dash-separated
  RequestForm request;
  ResponseForm response;
  bool broadcast_allowed;    // table 9.1 note 1: may be sent to address 00
  bool silent_on_broadcast;  // table 9.1 note 2: no reply when broadcast
};

std::span<const CommandInfo> command_table() noexcept;
const CommandInfo& command_info(CommandId id) noexcept;
const CommandInfo* find_command_by_code(std::string_view code) noexcept;  // exact, upper case
const CommandInfo* find_command_by_cli_name(std::string_view cli_name) noexcept;

// Number of characters after the command code in a request / in the matching reply.
std::size_t request_argument_length(RequestForm form) noexcept;
std::size_t reply_argument_length(const CommandInfo& command) noexcept;

}  // namespace rangekit::ls5
