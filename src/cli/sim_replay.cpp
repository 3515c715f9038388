// `rangekit sim replay FILE --port PATH`: the recorded sensor on a pty. Each request the host
// sends is answered with what the sensor said after it in the recording, at the recorded
// pace, so a problem seen on site reproduces at a desk with the host software.
#include <fmt/core.h>

#include <deque>

#include "cli/capture_replay.hpp"
#include "cli/cli_family.hpp"
#include "cli/commands.hpp"
#include "cli/describe.hpp"
#include "cli/recording_file.hpp"
#include "cli/replay_script.hpp"
#include "cli/sim.hpp"
#include "cli/stop_signals.hpp"
#include "rangekit/sim/pty.hpp"

namespace rangekit::cli {
namespace {

using Clock = std::chrono::steady_clock;

struct ReplayOptions {
  std::string file;
  std::string port;
  std::string family;  // empty: the recording's `family NAME` comment
  std::string source;  // a capture's sensor; empty: its first
};

int run_replay(const ReplayOptions& options) {
  if (is_capture_file(options.file)) {
    return run_capture_replay({options.file, options.port, options.family, options.source});
  }
  int code = exit_ok;
  auto file = read_recording("rangekit sim replay", options.file, options.family, code);
  if (!file) return code;
  const CliFamily* family = file->family;
  const FrameDecoder host_decoder = default_decoder(*family, Direction::to_device);
  ReplayScript script = ReplayScript::from_recording(file->recording, host_decoder.scan);
  auto pty = PseudoTerminal::open(options.port);
  if (!pty) {
    fmt::print(stderr, "rangekit sim replay: {}\n", pty.error().message);
    return exit_io;
  }
  // A host that closes the port and opens it again finds the same recorded sensor.
  if (auto held = (*pty)->hold_slave_open(); !held) {
    fmt::print(stderr, "rangekit sim replay: {}\n", held.error().message);
    return exit_io;
  }
  StopSignals signals;
  fmt::print("rangekit sim replay ready: {} ({}, {} requests recorded)\n", (*pty)->public_path(), family->label,
             script.requests());
  std::fflush(stdout);
  // What is due to be said, and when: a new request cuts what was left of the last answer.
  std::deque<std::pair<Clock::time_point, std::string>> due;
  const auto schedule = [&](const Answer& answer, Clock::time_point from) {
    due.clear();
    for (const TimedBytes& part : answer) due.emplace_back(from + part.after, part.bytes);
  };
  schedule(script.opening(), Clock::now());
  FrameAssembler host(host_decoder.scan, 4096);
  std::array<std::uint8_t, 4096> buffer{};
  std::uint64_t answered = 0;
  std::uint64_t unknown = 0;
  while (!signals.stopped()) {
    const auto now = Clock::now();
    while (!due.empty() && due.front().first <= now) {
      if (auto written = (*pty)->write_all(as_bytes(due.front().second)); !written) {
        fmt::print(stderr, "rangekit sim replay: {}\n", written.error().message);
        return exit_io;
      }
      due.pop_front();
    }
    auto wait = std::chrono::milliseconds(100);
    if (!due.empty()) {
      wait = std::clamp(std::chrono::duration_cast<std::chrono::milliseconds>(due.front().first - now),
                        std::chrono::milliseconds(0), wait);
    }
    auto read = (*pty)->read_some(buffer, wait);
    if (!read) {
      if (read.error().code == Errc::timeout) continue;
      fmt::print(stderr, "rangekit sim replay: {}\n", read.error().message);
      return exit_io;
    }
    const auto heard = Clock::now();
    FrameAssembler::Event event;
    feed_all(host, Bytes(buffer.data(), *read), [&] {
      while (host.next(event)) {
        if (event.kind != FrameAssembler::Event::Kind::frame) continue;
        if (const Answer* answer = script.answer(std::string(as_text(event.frame)))) {
          ++answered;
          schedule(*answer, heard);
        } else {
          ++unknown;
          due.clear();
          fmt::print(stderr, "rangekit sim replay: not in the recording, no answer: {}\n", printable(event.frame));
        }
      }
    });
  }
  fmt::print(stderr, "rangekit sim replay: {} requests answered from the recording, {} not in it\n", answered, unknown);
  return exit_interrupted;
}

}  // namespace

void add_sim_replay_command(CLI::App& sim, int& exit_code) {
  auto options = std::make_shared<ReplayOptions>();
  auto* replay = sim.add_subcommand(
      "replay",
      "Act as a recorded sensor on a pty: each request of a `tap --out` recording gets its recorded answer; a "
      "`capture` file's readings are streamed by the family's emulator");
  replay->add_option("file", options->file, "the recording (.pcapng) or capture (.sqlite)")->required();
  replay->add_option("--port", options->port, "symlink to the pty the host opens")->required();
  replay->add_option("--family", options->family,
                     "the family, when the recording does not name it, or a capture's: " + cli_family_names(" | "));
  replay->add_option("--source", options->source,
                     "a capture's sensor: its port or endpoint, and ' address N' on a bus (default: its first)");
  replay->footer("Exit codes: 130 after Ctrl-C, 3 a damaged recording, 4 the file or pty cannot be opened.");
  replay->callback([options, &exit_code] { exit_code = run_replay(*options); });
}

}  // namespace rangekit::cli
