// The ULS's part of the rangekit binary (cli/cli_family.hpp): its subcommands, its
// emulator, and what decode, tables, detect, capture and the demos ask of it.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>
#include <string>

#include "cli/cli_family.hpp"
#include "rangekit/uls/measurement.hpp"

namespace rangekit::cli {

// One ULS frame (without CR). From the device, BM lines are read with `context`.
std::string describe_uls_frame(Bytes frame, Direction direction, const uls::MeasurementContext& context);

struct UlsSourceOptions {
  std::string port;
  std::uint32_t baud = 115200;
  std::optional<std::uint8_t> address;  // RS-485 '#a' protocol
  std::string label;                    // Sample::source; default the port path
};
Result<SampleSourcePtr> start_uls_source(const UlsSourceOptions& options);

// Registration, one file each.
void add_uls_command(CLI::App& app, int& exit_code);
void add_sim_uls(CLI::App& sim, int& exit_code);
DecoderFactory add_uls_decode_options(CLI::App& decode);
Result<CaptureScene> uls_capture_scene(const CapturedReadings& readings);  // sim replay CAPTURE
SourceStarter add_uls_capture_options(CLI::App& capture);
DetectProbe add_uls_detect_options(CLI::App& detect);
extern const std::span<const CliTable> uls_tables;
extern const CliDemo uls_demo;
extern const CliDemoSite uls_demo_site;

}  // namespace rangekit::cli
