// The LS5's part of the rangekit binary (cli/cli_family.hpp), and what its subcommands
// share: the connection options, opening the driver (with a reopen function for
// reconnects), and the mapping of library errors to messages and exit codes (docs/cli.md).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "cli/cli_family.hpp"
#include "rangekit/core/result.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/ls5/driver.hpp"

namespace rangekit::cli {

struct Ls5Connection {
  std::string port;
  std::uint32_t baud = 115200;
  std::string byte_format = "8N1";
  std::string address = "1";
  int timeout_ms = 500;
};

// --port, --baud, --byte-format, --address, --timeout (and the hidden --timeout-ms).
void add_ls5_connection_options(CLI::App& command, Ls5Connection& connection);

// "5", "0x1A", "1A" (hex when it has hex letters) -> 1..255; 0 only with allow_broadcast.
Result<std::uint8_t> parse_ls5_address(std::string_view text, bool allow_broadcast = false);

// The line settings of a byte format name of table 9.2 (04): "8N1" ... "8O2".
Result<SerialSettings> ls5_serial_settings(std::uint32_t baud, std::string_view byte_format);

// Opens the port at the given baud and byte format and makes a driver on it. Address 0
// (broadcast, table 9.1 notes 1-2) only for commands that need no answer (L67).
// Without `with_reopen` the driver cannot reconnect: a stream ends when the port goes away.
Result<std::unique_ptr<ls5::Driver>> open_ls5_driver(const Ls5Connection& connection, bool allow_broadcast = false,
                                                     bool with_reopen = true);

// Prints "rangekit ls5 <command>: <message>" (plus a hint naming --port/--baud/--address
// when the sensor did not answer) and returns the exit code for the error.
int report_ls5_failure(std::string_view command, const Error& error, const Ls5Connection& connection);

// One LS5 frame (without CR); `range_mm` turns result codes into millimetres (0: codes only).
std::string describe_ls5_frame(Bytes frame, Direction direction, double range_mm);

struct Ls5SourceOptions {
  std::string port;
  std::uint32_t baud = 115200;
  std::uint8_t address = 0x01;
  std::optional<std::uint8_t> thinning;  // n of §8.4; the sensor's setting when empty
};
Result<SampleSourcePtr> start_ls5_source(const Ls5SourceOptions& options);

// Registration, one file each.
void add_ls5_command(CLI::App& app, int& exit_code);
void add_sim_ls5(CLI::App& sim, int& exit_code);
DecoderFactory add_ls5_decode_options(CLI::App& decode);
Result<CaptureScene> ls5_capture_scene(const CapturedReadings& readings);  // sim replay CAPTURE
SourceStarter add_ls5_capture_options(CLI::App& capture);
DetectProbe add_ls5_detect_options(CLI::App& detect);
extern const std::span<const CliTable> ls5_tables;
extern const CliDemo ls5_demo;
extern const CliDemoSite ls5_demo_site;
void add_ls5_device_commands(CLI::App& ls5, int& exit_code);  // info get set latch measure start stop save reset
void add_ls5_stream_commands(CLI::App& ls5, int& exit_code);  // stream udp
void add_ls5_config_command(CLI::App& ls5, int& exit_code);   // config save|load|diff

}  // namespace rangekit::cli
