// CLI edge of the stream loop (record/stream_loop.hpp): options, SIGINT/SIGTERM,
// the live status line on a terminal, messages and exit codes.
#include "cli/stream_runner.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <string>
#include <vector>

#include "cli/cli_family.hpp"
#include "cli/commands.hpp"
#include "cli/stop_signals.hpp"
#include "rangekit/record/diagnostic_limiter.hpp"
#include "rangekit/record/format.hpp"
#include "rangekit/record/stream_loop.hpp"

namespace rangekit::cli {
namespace {

std::string status_text(const record::StreamStats& stats) {
  const double rate = stats.elapsed_s > 0 ? static_cast<double>(stats.samples) / stats.elapsed_s : 0.0;
  std::string text = fmt::format("{} samples  {:.1f}/s  errors {}  lost {}  disconnects {}", stats.samples, rate,
                                 stats.errors, stats.lost, stats.disconnects);
  if (stats.suspect > 0) text += fmt::format("  suspect {}", stats.suspect);
  if (stats.dropped_suspect > 0) text += fmt::format(" ({} dropped)", stats.dropped_suspect);
  // Several sensors (capture): each one's rate, so a silent one is seen, not summed away.
  if (stats.sources.size() > 1) {
    for (const record::SourceCount& source : stats.sources) {
      const double own = stats.elapsed_s > 0 ? static_cast<double>(source.samples) / stats.elapsed_s : 0.0;
      text += fmt::format("  | {} {:.1f}/s", source.name, own);
    }
  }
  return text;
}

// The status line lives on stderr and is redrawn in place with \r; anything
// else written to the same terminal first clears it.
class StatusLine {
 public:
  explicit StatusLine(bool enabled) : enabled_(enabled) {}
  void show(const record::StreamStats& stats) {
    if (!enabled_) return;
    fmt::print(stderr, "\r{}\x1b[K", status_text(stats));
    std::fflush(stderr);
    shown_ = true;
  }
  void clear() {
    if (!shown_) return;
    fmt::print(stderr, "\r\x1b[K");
    std::fflush(stderr);
    shown_ = false;
  }
  [[nodiscard]] bool enabled() const { return enabled_; }

 private:
  bool enabled_;
  bool shown_ = false;
};

int exit_code_for(const record::StreamOutcome& outcome, const StreamOptions& options, const std::string& command_name) {
  switch (outcome.reason) {
    case record::StopReason::count_reached:
    case record::StopReason::duration_reached:
      return exit_ok;
    case record::StopReason::source_finished:
      if (outcome.stats.link_down && options.link_lost_is_failure) {
        fmt::print(stderr, "rangekit {}: the link went away and did not come back\n", command_name);
        return exit_link_lost;
      }
      return exit_ok;
    case record::StopReason::interrupted:
      fmt::print(stderr, "rangekit {}: interrupted after {} samples; files closed\n", command_name,
                 outcome.stats.samples);
      return exit_interrupted;
    case record::StopReason::open_failed:
      fmt::print(stderr, "rangekit {}: {}\n", command_name, outcome.error ? outcome.error->message : "cannot open");
      return exit_io;
    case record::StopReason::write_failed:
      fmt::print(stderr, "rangekit {}: {}\n", command_name, outcome.error ? outcome.error->message : "write failed");
      return exit_write_failed;
  }
  return exit_ok;
}

// Each family's default in words: "A 25, B its range a second".
std::string default_max_speeds() {
  std::string text;
  for (const CliFamily* family : cli_families()) {
    text += (text.empty() ? "" : ", ") + std::string(family->label) + " " + std::string(family->default_max_speed);
  }
  return text;
}

}  // namespace

void add_stream_options(CLI::App& command, StreamOptions& options, bool live) {
  command.add_option("--format", options.format, "output format: jsonl, csv or text")
      ->check(CLI::IsMember({"jsonl", "csv", "text"}))
      ->capture_default_str();
  command.add_option("--count", options.count, "stop after N samples")->check(sample_count());
  command.add_option("--duration", options.duration_s, "stop after S seconds")->check(duration_seconds());
  command.add_option("--out", options.out, "write the stream to FILE instead of standard output");
  command.add_option("--capture", options.capture, "also append everything to the SQLite capture FILE");
  command.add_flag("--quiet", options.quiet, "no live status line, even on a terminal");
  add_quality_options(command, options, live);
}

void add_quality_options(CLI::App& command, StreamOptions& options, bool live) {
  command.add_flag("--drop-suspect", options.drop_suspect,
                   "leave out samples marked suspect (a value no real target gives: a corrupted line)");
  if (live) {
    command
        .add_option("--max-speed", options.max_speed_mps,
                    "fastest the target moves, m/s: a faster jump is suspect (default: " + default_max_speeds() + ")")
        ->check(target_speed());
  }
}

int run_stream(SampleSource& source, const StreamOptions& options) { return run_stream_as(source, options, "stream"); }

int run_stream_as(SampleSource& source, const StreamOptions& options, const std::string& command_name,
                  record::StreamStats* stats_out) {
  auto format = record::parse_output_format(options.format);
  if (!format) {
    fmt::print(stderr, "rangekit {}: {}\n", command_name, format.error().message);
    return exit_usage;
  }
  record::StreamLoopOptions loop;
  loop.format = *format;
  loop.out = options.out;
  loop.capture = options.capture;
  loop.count = options.count;
  loop.duration_s = options.duration_s;
  if (options.check_quality) loop.quality = QualitySettings{options.max_speed_mps};
  loop.drop_suspect = options.drop_suspect;

  // Someone watches when standard output is a terminal: then the status line is
  // drawn (on stderr, so a terminal stdout keeps only the stream). A pipe or file
  // on stdout means a program reads it: plain output only (docs/cli.md).
  const bool stdout_on_terminal = ::isatty(STDOUT_FILENO) == 1;
  const bool output_on_terminal = options.out.empty() && stdout_on_terminal;
  StatusLine status(!options.quiet && stdout_on_terminal && ::isatty(STDERR_FILENO) == 1);
  record::StreamObserver observer;
  // A babbling line rejects thousands of fragments a second: the first of each kind is
  // printed, the rest merged into one summary a second.
  record::DiagnosticLimiter limiter;
  const auto print = [&status, &command_name](const std::vector<std::string>& lines) {
    if (lines.empty()) return;
    status.clear();
    for (const auto& line : lines) fmt::print(stderr, "rangekit {}: {}", command_name, line);
  };
  observer.on_event = [&limiter, &print](const StreamEvent& event) {
    print(limiter.on_event(event, std::chrono::steady_clock::now()));
  };
  observer.on_status = [&limiter, &print, &status](const record::StreamStats& stats) {
    print(limiter.tick(std::chrono::steady_clock::now()));
    status.show(stats);
  };
  if (status.enabled()) {
    if (output_on_terminal) {
      observer.before_output_flush = [&status] { status.clear(); };
      observer.after_output_flush = [&status](const record::StreamStats& stats) { status.show(stats); };
    }
  }

  StopSignals signals;
  const auto outcome = record::run_stream_loop(source, loop, signals.flag(), observer);
  print(limiter.finish(std::chrono::steady_clock::now()));
  status.clear();
  if (status.enabled()) fmt::print(stderr, "{}\n", status_text(outcome.stats));
  if (stats_out != nullptr) *stats_out = outcome.stats;
  return exit_code_for(outcome, options, command_name);
}

}  // namespace rangekit::cli
