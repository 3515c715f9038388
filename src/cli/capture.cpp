// `rangekit capture`: several sensors (ULS and LS5 ports) streamed into one
// SQLite capture, for long unattended runs; `replay` reads it back.
#include <fmt/core.h>

#include <vector>

#include "cli/commands.hpp"
#include "cli/host_sources.hpp"
#include "cli/stream_runner.hpp"
#include "rangekit/record/merge.hpp"

namespace rangekit::cli {
namespace {

struct CaptureArguments {
  std::vector<std::string> uls_ports;
  std::uint32_t uls_baud = 115200;
  std::vector<std::string> ls5_ports;
  std::uint32_t ls5_baud = 115200;
  unsigned ls5_address = 1;
  std::optional<unsigned> ls5_thinning;
  std::string echo;  // "" = nothing on stdout
  StreamOptions stream;
};

int run_capture(CaptureArguments& arguments) {
  if (arguments.uls_ports.empty() && arguments.ls5_ports.empty()) {
    fmt::print(stderr, "rangekit capture: give at least one --uls PORT or --ls5 PORT\n");
    return exit_usage;
  }
  std::vector<SampleSourcePtr> sources;
  for (const auto& port : arguments.uls_ports) {
    auto source = start_uls_source(UlsSourceOptions{port, arguments.uls_baud, std::nullopt, port});
    if (!source) {
      fmt::print(stderr, "rangekit capture: {}\n", source.error().message);
      return exit_code_for(source.error());
    }
    sources.push_back(std::move(source).value());
  }
  for (const auto& port : arguments.ls5_ports) {
    std::optional<std::uint8_t> thinning;
    if (arguments.ls5_thinning) thinning = static_cast<std::uint8_t>(*arguments.ls5_thinning);
    auto source = start_ls5_source(
        Ls5SourceOptions{port, arguments.ls5_baud, static_cast<std::uint8_t>(arguments.ls5_address), thinning});
    if (!source) {
      fmt::print(stderr, "rangekit capture: {}\n", source.error().message);
      return exit_code_for(source.error());
    }
    sources.push_back(std::move(source).value());
  }
  auto merged = record::merge_sources(std::move(sources));
  StreamOptions options = arguments.stream;
  if (arguments.echo.empty()) {
    options.out = "/dev/null";
    options.format = "jsonl";
  } else {
    options.format = arguments.echo;
  }
  record::StreamStats stats;
  const int code = run_stream_as(*merged, options, "capture", &stats);
  // No silent end (docs/cli.md): what the file holds and how to look at it; said
  // only when there is a file to replay (not after "cannot open" it).
  const bool file_written = code == exit_ok || code == exit_interrupted || stats.samples > 0;
  if (file_written)
    fmt::print(stderr, "rangekit capture: {} samples \u2192 {}; replay with: rangekit replay {}\n", stats.samples,
               options.capture, options.capture);
  return code;
}

}  // namespace

void add_capture_command(CLI::App& app, int& exit_code) {
  static CaptureArguments arguments;
  auto* command = app.add_subcommand(
      "capture", "Stream ULS and LS5 sensors into one SQLite capture (append-only, WAL; see docs/capture.md)");
  command->add_option("--out", arguments.stream.capture, "SQLite capture file (appended to when it exists)")
      ->required();
  command->add_option("--uls", arguments.uls_ports, "ULS serial port (repeat for several)");
  command->add_option("--uls-baud", arguments.uls_baud, "baud rate of the ULS ports")->capture_default_str();
  command->add_option("--ls5", arguments.ls5_ports, "LS5 serial port (repeat for several)");
  command->add_option("--ls5-baud", arguments.ls5_baud, "baud rate of the LS5 ports")->capture_default_str();
  command->add_option("--ls5-address", arguments.ls5_address, "LS5 network address")
      ->check(CLI::Range(1, 255))
      ->capture_default_str();
  command->add_option("--ls5-thinning", arguments.ls5_thinning, "LS5 stream thinning n (§8.4)")
      ->check(CLI::Range(1, 255));
  command->add_option("--count", arguments.stream.count, "stop after this many samples")->check(sample_count());
  command->add_option("--duration", arguments.stream.duration_s, "stop after this many seconds")
      ->check(duration_seconds());
  command->add_option("--echo", arguments.echo, "also print the samples: jsonl, csv or text")
      ->check(CLI::IsMember({"jsonl", "csv", "text"}));
  command->add_flag("--quiet", arguments.stream.quiet, "no live status line");
  add_quality_options(*command, arguments.stream);
  command->callback([&exit_code] { exit_code = run_capture(arguments); });
}

}  // namespace rangekit::cli
