// `rangekit tap FAMILY`: a transparent man-in-the-middle between a host and a sensor. Two
// threads forward the bytes each way as they come and only hand a copy on; this thread
// decodes the copies, prints them and records them, so a slow terminal never slows the line.
#include <fmt/core.h>
#include <unistd.h>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <fstream>
#include <mutex>
#include <thread>

#include "cli/cli_family.hpp"
#include "cli/commands.hpp"
#include "cli/host_sources.hpp"
#include "cli/stop_signals.hpp"
#include "cli/tap_report.hpp"
#include "rangekit/record/pcapng.hpp"
#include "rangekit/sim/pty.hpp"

namespace rangekit::cli {
namespace {

struct TapOptions {
  std::string host;
  std::string host_pty;
  std::string sensor;
  std::uint32_t baud = 9600;
  std::string byte_format = "8N1";
  std::string format = "text";
  std::string out;
  std::uint64_t every = 100;
  double duration_s = 0;
};

// The chunks the forwarders read, for this thread; bounded, so a report that falls behind
// loses its oldest copies (counted), never the line's bytes.
struct ChunkQueue {
  static constexpr std::size_t limit = 100000;
  std::mutex mutex;
  std::condition_variable ready;
  std::deque<record::SerialChunk> chunks;
  std::uint64_t lost = 0;
  std::string failure;  // the first forwarding error: the tap ends
  bool done = false;

  void push(record::SerialChunk chunk) {
    {
      const std::lock_guard lock(mutex);
      chunks.push_back(std::move(chunk));
      if (chunks.size() > limit) {
        chunks.pop_front();
        ++lost;
      }
    }
    ready.notify_one();
  }
  void fail(const std::string& why) {
    {
      const std::lock_guard lock(mutex);
      if (failure.empty()) failure = why;
      done = true;
    }
    ready.notify_one();
  }
};

// Reads `from` and writes each chunk to `to` at once, with a copy queued for the report.
void forward(Transport& from, Transport& to, record::Sender sender, const std::atomic<bool>& stopping,
             ChunkQueue& queue) {
  std::array<std::uint8_t, 4096> buffer{};
  while (!stopping) {
    auto read = from.read_some(buffer, std::chrono::milliseconds(100));
    if (!read) {
      if (read.error().code == Errc::timeout) continue;
      queue.fail(from.name() + ": " + read.error().message);
      return;
    }
    if (*read == 0) continue;
    const auto time = std::chrono::system_clock::now();
    const Bytes bytes(buffer.data(), *read);
    // Queued before it is written, so a request is always queued before its reply can be read.
    queue.push(record::SerialChunk{sender, time, std::string(as_text(bytes))});
    if (auto written = to.write_all(bytes); !written) {
      queue.fail(to.name() + ": " + written.error().message);
      return;
    }
  }
}

int run_tap(const TapOptions& options, const CliFamily& family, const DecoderFactory& decoder_of) {
  auto settings = serial_settings(options.baud, options.byte_format);
  if (!settings) {
    fmt::print(stderr, "rangekit tap: {}\n", settings.error().message);
    return exit_usage;
  }
  auto sensor = open_port(options.sensor, *settings);
  if (!sensor) {
    fmt::print(stderr, "rangekit tap: {}\n", sensor.error().message);
    return exit_code_for(sensor.error());
  }
  TransportPtr host;
  std::string host_name = options.host;
  if (!options.host_pty.empty()) {
    auto pty = PseudoTerminal::open(options.host_pty);
    if (!pty) {
      fmt::print(stderr, "rangekit tap: --host-pty {}: {}\n", options.host_pty, pty.error().message);
      return exit_code_for(pty.error());
    }
    // A host program that closes the port and opens it again keeps its tap.
    if (auto held = (*pty)->hold_slave_open(); !held) {
      fmt::print(stderr, "rangekit tap: {}\n", held.error().message);
      return exit_io;
    }
    host_name = (*pty)->public_path();
    host = std::move(*pty);
  } else {
    auto opened = open_port(options.host, *settings);
    if (!opened) {
      fmt::print(stderr, "rangekit tap: {}\n", opened.error().message);
      return exit_code_for(opened.error());
    }
    host = std::move(*opened);
  }
  std::ofstream recording;
  if (!options.out.empty()) {
    recording.open(options.out, std::ios::binary | std::ios::trunc);
    if (!recording) {
      fmt::print(stderr, "rangekit tap: cannot write {}\n", options.out);
      return exit_write_failed;
    }
    recording << record::pcapng_section_header({"family " + std::string(family.name), "line " + describe(*settings),
                                                "host " + host_name, "sensor " + options.sensor},
                                               "rangekit tap");
    recording << record::pcapng_serial_interface(host_name + " <-> " + options.sensor);
  }
  const bool jsonl = options.format == "jsonl";
  TapReport report(decoder_of(Direction::to_device), decoder_of(Direction::from_device),
                   jsonl ? TapFormat::jsonl : TapFormat::text, options.every, !jsonl && ::isatty(STDOUT_FILENO) == 1);
  // Progress on stderr, so that stdout is the conversation alone (jsonl for a pipe).
  fmt::print(stderr, "rangekit tap: {} {} <-> {} at {}; Ctrl-C ends{}\n", family.label, host_name, options.sensor,
             describe(*settings), options.out.empty() ? "" : ", recording to " + options.out);
  StopSignals signals;
  std::atomic<bool> stopping{false};
  ChunkQueue queue;
  std::thread to_sensor([&] { forward(*host, **sensor, record::Sender::host, stopping, queue); });
  std::thread to_host([&] { forward(**sensor, *host, record::Sender::sensor, stopping, queue); });
  const auto until = options.duration_s > 0 ? std::chrono::steady_clock::now() +
                                                  std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                      std::chrono::duration<double>(options.duration_s))
                                            : std::chrono::steady_clock::time_point::max();
  const auto print = [](const std::vector<std::string>& lines) {
    for (const std::string& line : lines) fmt::print("{}\n", line);
    if (!lines.empty()) std::fflush(stdout);
  };
  bool failed = false;
  for (;;) {
    std::deque<record::SerialChunk> taken;
    {
      std::unique_lock lock(queue.mutex);
      queue.ready.wait_for(lock, std::chrono::milliseconds(100), [&] { return !queue.chunks.empty() || queue.done; });
      taken.swap(queue.chunks);
      failed = !queue.failure.empty();
    }
    for (const record::SerialChunk& chunk : taken) {
      if (recording.is_open()) recording << record::pcapng_serial_packet(chunk);
      print(report.add(chunk));
    }
    if (recording.is_open()) recording.flush();
    if (failed || signals.stopped() || std::chrono::steady_clock::now() >= until) break;
  }
  stopping = true;
  to_sensor.join();
  to_host.join();
  for (const record::SerialChunk& chunk : queue.chunks) {  // read while the threads ended
    if (recording.is_open()) recording << record::pcapng_serial_packet(chunk);
    print(report.add(chunk));
  }
  print(report.finish());
  const TapCounts& counts = report.counts();
  fmt::print(stderr, "rangekit tap: host {} frames, sensor {} ({} replies, {} streamed), {} rejected runs of bytes{}\n",
             counts.host_frames, counts.sensor_frames, counts.replies, counts.streamed, counts.rejected,
             queue.lost > 0 ? fmt::format(", {} chunks not decoded (the report fell behind)", queue.lost) : "");
  if (recording.is_open() && !recording.good()) {
    fmt::print(stderr, "rangekit tap: writing {} failed\n", options.out);
    return exit_write_failed;
  }
  if (failed) {
    fmt::print(stderr, "rangekit tap: {}\n", queue.failure);
    return exit_link_lost;
  }
  return signals.stopped() ? exit_interrupted : exit_ok;
}

}  // namespace

void add_tap_command(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<TapOptions>();
  auto* command = app.add_subcommand(
      "tap", "Sit between a host (a PLC, the vendor's program) and a sensor: forward, decode and record both ways");
  command->require_subcommand(1);
  command->footer(
      "Exit codes: 0 done (--duration), 130 Ctrl-C, 4 a port cannot be opened, 8 a port went away, 7 the "
      "recording could not be written.");
  for (const CliFamily* family : cli_families()) {
    auto* tap = command->add_subcommand(std::string(family->name),
                                        "Tap a " + std::string(family->label) + " line, decoding its frames");
    auto* host = tap->add_option("--host", options->host, "the host's port (a PLC or PC wired to this adapter)");
    auto* host_pty = tap->add_option("--host-pty", options->host_pty,
                                     "make a pty at PATH for a host program on this machine to open instead");
    host->excludes(host_pty);
    host_pty->excludes(host);
    tap->add_option("--sensor", options->sensor, "the sensor's port")->required();
    tap->add_option("--baud", options->baud, "the line's baud rate (default 9600)");
    tap->add_option("--byte-format", options->byte_format, "the line's byte format: 8N1 (default), 8E1, 8O1, 8N2 ...");
    tap->add_option("--format", options->format, "text (default; coloured on a terminal) or jsonl, one record a frame")
        ->check(CLI::IsMember({"text", "jsonl"}));
    tap->add_option("--out", options->out, "record both directions to FILE.pcapng (Wireshark, tshark)");
    tap->add_option("--every", options->every, "text: show every Nth frame of a stream (default 100)")
        ->check(CLI::Range(1, 1000000));
    tap->add_option("--duration", options->duration_s, "stop after this many seconds (default: until Ctrl-C)")
        ->check(duration_seconds());
    tap->callback([options, family, decoder_of = family->add_decode_options(*tap), &exit_code] {
      if (options->host.empty() && options->host_pty.empty()) {
        fmt::print(stderr, "rangekit tap {}: give --host PORT or --host-pty PATH\n", family->name);
        exit_code = exit_usage;
        return;
      }
      exit_code = run_tap(*options, *family, decoder_of);
    });
  }
  add_tap_compare_command(*command, exit_code);
}

}  // namespace rangekit::cli
