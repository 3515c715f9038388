// `rangekit ls5 ...`: configure, read and stream a Prizma LS5 (docs/host-ls5.md). The
// subcommands live in ls5_*.cpp; this file registers them and holds what they share.
#include <fmt/core.h>

#include <charconv>

#include "cli/commands.hpp"
#include "cli/host_sources.hpp"
#include "ls5/cli/ls5_cli.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/ls5/settings.hpp"

namespace rangekit::cli {

Result<SerialSettings> ls5_serial_settings(std::uint32_t baud, std::string_view byte_format) {
  SerialSettings settings;
  settings.baud = baud;
  for (const ls5::ByteFormat& format : ls5::byte_format_table()) {
    if (format.name != byte_format) continue;
    settings.parity = format.parity == ls5::Parity::none   ? Parity::none
                      : format.parity == ls5::Parity::even ? Parity::even
                                                           : Parity::odd;
    settings.stop_bits = format.stop_bits;
    return settings;
  }
  return make_error(Errc::out_of_range, "--byte-format " + std::string(byte_format) +
                                            " is not one of 8N1 8E1 8O1 8N2 8E2 8O2 (table 9.2, 04)");
}

void add_ls5_connection_options(CLI::App& command, Ls5Connection& connection) {
  command.add_option("--port", connection.port, "serial port or pty of the sensor (e.g. /dev/ttyUSB0)")->required();
  command.add_option("--baud", connection.baud, "baud rate (default 115200, the sensor's default)");
  command.add_option("--byte-format", connection.byte_format, "8N1 8E1 8O1 8N2 8E2 8O2 (default 8N1)");
  command.add_option("--address", connection.address,
                     "network address 1-255, decimal or 0x.. (default 1); 0 broadcasts set/on/off/save/defaults/latch "
                     "to every sensor, unanswered");
  command.add_option("--timeout", connection.timeout_ms, "milliseconds to wait for each reply (default 500)")
      ->check(timeout_milliseconds());
  // A hidden alias kept for existing scripts; `--timeout` as for the ULS.
  command.add_option("--timeout-ms", connection.timeout_ms)->check(timeout_milliseconds())->group("");
}

Result<std::uint8_t> parse_ls5_address(std::string_view text, bool allow_broadcast) {
  int base = 10;
  if (text.size() > 2 && (text.substr(0, 2) == "0x" || text.substr(0, 2) == "0X")) {
    text.remove_prefix(2);
    base = 16;
  }
  unsigned value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value, base);
  const unsigned lowest = allow_broadcast ? 0 : 1;
  if (text.empty() || error != std::errc{} || end != text.data() + text.size() || value < lowest || value > 255) {
    return make_error(Errc::out_of_range, "--address '" + std::string(text) + "' must be " + std::to_string(lowest) +
                                              "-255 (decimal, or hex as 0x1A)");
  }
  return static_cast<std::uint8_t>(value);
}

Result<std::unique_ptr<ls5::Driver>> open_ls5_driver(const Ls5Connection& connection, bool allow_broadcast,
                                                     bool with_reopen) {
  auto address = parse_ls5_address(connection.address, true);
  if (!address) return address.error();
  if (*address == ls5::broadcast_address && !allow_broadcast) {
    return make_error(Errc::wrong_form,
                      "--address 0 is the broadcast address, which no sensor answers (table 9.1 note 2), and this "
                      "command needs an answer: give the sensor's address 1-255");
  }
  auto settings = ls5_serial_settings(connection.baud, connection.byte_format);
  if (!settings) return settings.error();
  auto port = open_port(connection.port, *settings);
  if (!port) return port.error();
  ls5::DriverOptions options;
  options.address = *address;
  options.timeout = std::chrono::milliseconds(connection.timeout_ms);
  return std::make_unique<ls5::Driver>(std::move(*port), options,
                                       with_reopen ? reopen_port(connection.port, *settings) : ls5::ReopenFunction{});
}
int report_ls5_failure(std::string_view command, const Error& error, const Ls5Connection& connection) {
  fmt::print(stderr, "rangekit ls5 {}: {}\n", command, error.message);
  if (error.code == Errc::timeout) {
    fmt::print(stderr,
               "  hint: is --port {} the sensor's port, does it run at --baud {} --byte-format {}, and is its "
               "--address {}? (factory settings: 115200 8N1, address 1)\n",
               connection.port, connection.baud, connection.byte_format, connection.address);
  }
  return exit_code_for(error);
}
void add_ls5_command(CLI::App& app, int& exit_code) {
  auto* ls5 = app.add_subcommand("ls5", "configure, read and stream a Prizma LS5 laser triangulation sensor");
  ls5->require_subcommand(1);
  // The document's sections stay here and in docs/conformance.md, out of the messages.
  ls5->footer("Manual: §8, tables 9.1 and 9.2, §10 Ethernet; docs/host-ls5.md");
  add_ls5_device_commands(*ls5, exit_code);
  add_ls5_stream_commands(*ls5, exit_code);
  add_ls5_config_command(*ls5, exit_code);
}

}  // namespace rangekit::cli
