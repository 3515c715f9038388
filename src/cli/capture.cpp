// `rangekit capture`: several sensors (ports of any family) streamed into one
// SQLite capture, for long unattended runs; `replay` reads it back.
#include <fmt/core.h>

#include <vector>

#include "cli/cli_family.hpp"
#include "cli/commands.hpp"
#include "cli/stream_runner.hpp"
#include "rangekit/record/merge.hpp"

namespace rangekit::cli {
namespace {

struct CaptureArguments {
  std::vector<SourceStarter> starters;  // each family's, from its options
  std::string echo;                     // "" = nothing on stdout
  StreamOptions stream;
};

// "--a PORT or --b PORT"
std::string port_options() {
  std::string text;
  for (const CliFamily* family : cli_families()) {
    text += (text.empty() ? "--" : " or --") + std::string(family->name) + " PORT";
  }
  return text;
}

int run_capture(CaptureArguments& arguments) {
  std::vector<SampleSourcePtr> sources;
  for (const SourceStarter& start : arguments.starters) {
    auto started = start();
    if (!started) {
      fmt::print(stderr, "rangekit capture: {}\n", started.error().message);
      return exit_code_for(started.error());
    }
    for (auto& source : *started) sources.push_back(std::move(source));
  }
  if (sources.empty()) {
    fmt::print(stderr, "rangekit capture: give at least one {}\n", port_options());
    return exit_usage;
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
  if (file_written) {
    // Each sensor's share, so one that sent nothing is seen ("uls /dev/ttyUSB0 0").
    std::string shares;
    if (stats.sources.size() > 1) {
      for (const record::SourceCount& source : stats.sources)
        shares += (shares.empty() ? " (" : ", ") + source.name + " " + std::to_string(source.samples);
      shares += ")";
    }
    fmt::print(stderr, "rangekit capture: {} samples{} \u2192 {}; replay with: rangekit replay {}\n", stats.samples,
               shares, options.capture, options.capture);
  }
  return code;
}

}  // namespace

void add_capture_command(CLI::App& app, int& exit_code) {
  static CaptureArguments arguments;
  auto* command =
      app.add_subcommand("capture", "Stream " + cli_family_labels(" and ") +
                                        " sensors into one SQLite capture (append-only, WAL; see docs/capture.md)");
  command->add_option("--out", arguments.stream.capture, "SQLite capture file (appended to when it exists)")
      ->required();
  for (const CliFamily* family : cli_families()) arguments.starters.push_back(family->add_capture_options(*command));
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
