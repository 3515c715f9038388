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
#include "cli/tap_output.hpp"
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
  std::string family;  // empty or "auto": told from the traffic
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

int run_tap(const TapOptions& options, const CliFamily* family, const DecoderFactory& decoder_of) {
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
  }
  const bool jsonl = options.format == "jsonl";
  TapOutputSettings output_settings{jsonl ? TapFormat::jsonl : TapFormat::text,
                                    options.every,
                                    !jsonl && ::isatty(STDOUT_FILENO) == 1,
                                    {"line " + describe(*settings), "host " + host_name, "sensor " + options.sensor},
                                    host_name + " <-> " + options.sensor};
  TapOutput output(std::move(output_settings), recording.is_open() ? &recording : nullptr, family, decoder_of,
                   [](const std::string& note) { fmt::print(stderr, "rangekit tap: {}\n", note); });
  // Progress on stderr, so that stdout is the conversation alone (jsonl for a pipe).
  fmt::print(stderr, "rangekit tap: {} <-> {} at {}, {}; Ctrl-C ends{}\n", host_name, options.sensor,
             describe(*settings), family != nullptr ? std::string(family->label) : "the family told from the traffic",
             options.out.empty() ? "" : ", recording to " + options.out);
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
  std::array<std::uint64_t, 2> bytes_from{};  // host, sensor
  const auto take = [&](const record::SerialChunk& chunk) {
    bytes_from.at(chunk.sender == record::Sender::host ? 0 : 1) += chunk.bytes.size();
    print(output.add(chunk));
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
    for (const record::SerialChunk& chunk : taken) take(chunk);
    if (recording.is_open()) recording.flush();
    if (failed || signals.stopped() || std::chrono::steady_clock::now() >= until) break;
  }
  stopping = true;
  to_sensor.join();
  to_host.join();
  for (const record::SerialChunk& chunk : queue.chunks) take(chunk);  // read while the threads ended
  print(output.finish());
  std::string frames;
  if (const TapCounts* counts = output.counts()) {
    frames =
        fmt::format("; host {} frames, sensor {} ({} replies, {} streamed), {} rejected runs of bytes",
                    counts->host_frames, counts->sensor_frames, counts->replies, counts->streamed, counts->rejected);
  }
  fmt::print(stderr, "rangekit tap: forwarded {} bytes from the host, {} from the sensor{}{}\n", bytes_from[0],
             bytes_from[1], frames,
             queue.lost > 0
                 ? fmt::format(", {} chunks neither decoded nor recorded (the report fell behind)", queue.lost)
                 : "");
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
  command->require_subcommand(0, 1);
  command->footer(
      "The family is told from the traffic, or given: --family NAME, or `tap NAME` with that family's decode "
      "options (`rangekit tap NAME --help`).\n"
      "Exit codes: 0 done (--duration), 130 Ctrl-C, 4 a port cannot be opened, 8 a port went away, 7 the "
      "recording could not be written.");
  auto* host = command->add_option("--host", options->host, "the host's port (a PLC or PC wired to this adapter)");
  auto* host_pty = command->add_option("--host-pty", options->host_pty,
                                       "make a pty at PATH for a host program on this machine to open instead");
  host->excludes(host_pty);
  host_pty->excludes(host);
  command->add_option("--sensor", options->sensor, "the sensor's port");
  command
      ->add_option("--family", options->family, "the line's family: " + cli_family_names(", ") + " or auto (default)")
      ->check(CLI::IsMember([] {
        auto names = cli_family_name_list();
        names.emplace_back("auto");
        return names;
      }()));
  command->add_option("--baud", options->baud, "the line's baud rate (default 9600)");
  command->add_option("--byte-format", options->byte_format,
                      "the line's byte format: 8N1 (default), 8E1, 8O1, 8N2 ...");
  command
      ->add_option("--format", options->format, "text (default; coloured on a terminal) or jsonl, one record a frame")
      ->check(CLI::IsMember({"text", "jsonl"}));
  command->add_option("--out", options->out, "record both directions to FILE.pcapng (Wireshark, tshark)");
  command->add_option("--every", options->every, "text: show every Nth frame of a stream (default 100)")
      ->check(CLI::Range(1, 1000000));
  command->add_option("--duration", options->duration_s, "stop after this many seconds (default: until Ctrl-C)")
      ->check(duration_seconds());
  // `tap NAME`: the family given, with its decode options; the line's options stay the tap's own.
  auto decoders = std::make_shared<std::vector<std::pair<CLI::App*, DecoderFactory>>>();
  for (const CliFamily* family : cli_families()) {
    auto* tap = command->add_subcommand(std::string(family->name),
                                        "Tap a " + std::string(family->label) + " line, with its decode options");
    tap->fallthrough();
    decoders->emplace_back(tap, family->add_decode_options(*tap));
  }
  auto* compare = add_tap_compare_command(*command, exit_code);
  command->callback([compare, options, decoders, &exit_code] {
    if (compare->parsed()) return;
    const CliFamily* family = nullptr;
    DecoderFactory decoder_of;
    for (const auto& [tap, factory] : *decoders) {
      if (tap->parsed()) {
        family = find_cli_family(tap->get_name());
        decoder_of = factory;
      }
    }
    if (!options->family.empty() && options->family != "auto") {
      const CliFamily* named = find_cli_family(options->family);
      if (family != nullptr && family != named) {
        fmt::print(stderr, "rangekit tap: `tap {}` and --family {} disagree\n", family->name, options->family);
        exit_code = exit_usage;
        return;
      }
      family = named;
    }
    if (options->sensor.empty() || (options->host.empty() && options->host_pty.empty())) {
      fmt::print(stderr, "rangekit tap: give --sensor PORT and --host PORT or --host-pty PATH (rangekit tap --help)\n");
      exit_code = exit_usage;
      return;
    }
    exit_code = run_tap(*options, family, decoder_of);
  });
}

}  // namespace rangekit::cli
