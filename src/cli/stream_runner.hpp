// The loop behind every `stream` subcommand and `replay`: samples to stdout/--out and/or
// a --capture until --count/--duration/Ctrl-C, with a status line on a terminal and the
// exit codes of docs/cli.md.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>

#include "rangekit/core/sample.hpp"
#include "rangekit/record/stream_loop.hpp"

namespace rangekit::cli {

struct StreamOptions {
  std::string format = "text";         // jsonl | csv | text
  std::optional<std::uint64_t> count;  // stop after this many samples
  std::optional<double> duration_s;    // stop after this many seconds
  std::string out;                     // file for the formatted stream ("" = stdout)
  std::string capture;                 // SQLite capture file ("" = none)
  bool quiet = false;                  // no live status line even on a tty
  // A live source that ends after a disconnect exits with exit_link_lost; a
  // replay only shows the recorded disconnect.
  bool link_lost_is_failure = true;
  // Quality (docs/reliability.md): live streams check each sample; a replay keeps the flags
  // recorded with it. --drop-suspect leaves suspect samples out of every output.
  bool check_quality = true;
  std::optional<double> max_speed_mps;  // --max-speed; nullopt = the family default
  bool drop_suspect = false;
};

// Adds --format, --count, --duration, --out, --capture, --quiet and --drop-suspect to a
// subcommand, and --max-speed when it reads a live sensor (`live`).
void add_stream_options(CLI::App& command, StreamOptions& options, bool live = true);
// Only --drop-suspect and (live) --max-speed, for a command with its own other options.
void add_quality_options(CLI::App& command, StreamOptions& options, bool live = true);

// Runs until the source finishes, the limits are reached or SIGINT/SIGTERM.
// Returns an exit code of commands.hpp (exit_ok, exit_write_failed, exit_interrupted, ...).
int run_stream(SampleSource& source, const StreamOptions& options);
// The same, naming the subcommand in messages ("rangekit replay: ..."); `stats`,
// when given, receives the loop's counts (samples written, errors, lost).
int run_stream_as(SampleSource& source, const StreamOptions& options, const std::string& command_name,
                  record::StreamStats* stats = nullptr);

}  // namespace rangekit::cli
