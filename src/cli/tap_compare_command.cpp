// `rangekit tap compare FILE`: the recorded host requests sent to the family's emulator, its
// answers compared with the recorded ones (tap_compare.hpp): what measures the emulators
// against a real unit.
#include <fmt/core.h>
#include <stdlib.h>

#include <filesystem>

#include "cli/capture_replay.hpp"
#include "cli/cli_family.hpp"
#include "cli/commands.hpp"
#include "cli/host_sources.hpp"
#include "cli/recording_file.hpp"
#include "cli/sim_process.hpp"
#include "cli/tap_compare.hpp"

namespace rangekit::cli {
namespace {

using Clock = std::chrono::steady_clock;

struct CompareOptions {
  std::string file;
  std::string family;
};

// The emulator's answer to one request: its frames until as many as were recorded came (a
// stream: compared_frames + 1), or nothing more came for a while.
std::vector<TimedFrame> ask(Transport& port, const Exchange& exchange, const FrameDecoder& sensor) {
  std::array<std::uint8_t, 4096> buffer{};
  while (port.read_some(buffer, std::chrono::milliseconds(0)).value_or(0) > 0) {
    // what an earlier answer left (a stream) is not this one's
  }
  const std::size_t wanted = std::min(exchange.answer.size(), compared_frames + 1);
  const auto recorded_span = exchange.answer.empty() ? std::chrono::microseconds(0) : exchange.answer[wanted - 1].after;
  const auto patience = std::max<Clock::duration>(recorded_span * 2, std::chrono::milliseconds(300));
  std::vector<TimedFrame> frames;
  const auto sent = Clock::now();
  if (!port.write_all(as_bytes(exchange.request_wire))) return frames;
  FrameAssembler assembler(sensor.scan, 4096);
  while (frames.size() < std::max<std::size_t>(wanted, 1) && Clock::now() - sent < patience) {
    auto read = port.read_some(buffer, std::chrono::milliseconds(20));
    if (!read || *read == 0) continue;
    const auto after = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - sent);
    FrameAssembler::Event event;
    feed_all(assembler, Bytes(buffer.data(), *read), [&] {
      while (assembler.next(event)) {
        if (event.kind == FrameAssembler::Event::Kind::frame)
          frames.push_back({after, std::string(as_text(event.frame))});
      }
    });
  }
  return frames;
}

int run_compare(const CompareOptions& options) {
  if (is_capture_file(options.file)) {
    fmt::print(stderr,
               "rangekit tap compare: {} is a capture: it keeps the readings, not the host's requests to compare "
               "answers to; record the conversation with `rangekit tap --out FILE.pcapng`\n",
               options.file);
    return exit_bad_input;
  }
  int code = exit_ok;
  auto file = read_recording("rangekit tap compare", options.file, options.family, code);
  if (!file) return code;
  const CliFamily* family = file->family;
  const record::SerialRecording& recording = file->recording;
  // "115200 8N1", as the tap wrote it; 115200 8N1 when the recording does not say.
  const std::string line = comment_value(recording, "line");
  const auto space = line.find(' ');
  std::uint32_t baud = 115200;
  if (space != std::string::npos) baud = static_cast<std::uint32_t>(std::strtoul(line.c_str(), nullptr, 10));
  auto settings = serial_settings(baud, space == std::string::npos ? "8N1" : line.substr(space + 1));
  if (!settings) {
    fmt::print(stderr, "rangekit tap compare: {}: line '{}': {}\n", options.file, line, settings.error().message);
    return exit_bad_input;
  }
  const DecoderFactory decoders = default_decoders(*family);
  const FrameDecoder host = decoders(Direction::to_device);
  const FrameDecoder sensor = decoders(Direction::from_device);
  const std::vector<Exchange> exchanges = exchanges_of(recording, host, sensor);
  std::string pattern = (std::filesystem::temp_directory_path() / "rangekit-compare-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr) {
    fmt::print(stderr, "rangekit tap compare: cannot make a folder for the emulator\n");
    return exit_io;
  }
  const std::filesystem::path dir = pattern;
  const std::string port_path = (dir / std::string(family->name)).string();
  {
    auto sim = SimProcess::start({std::string(family->name), "--port", port_path}, (dir / "sim.log").string(),
                                 std::chrono::seconds(20));
    if (!sim) {
      fmt::print(stderr, "rangekit tap compare: the {} emulator did not start: {}\n", family->label,
                 sim.error().message);
      std::filesystem::remove_all(dir);
      return exit_io;
    }
    auto port = open_port(port_path, *settings);
    if (!port) {
      fmt::print(stderr, "rangekit tap compare: {}\n", port.error().message);
      std::filesystem::remove_all(dir);
      return exit_io;
    }
    fmt::print("rangekit tap compare: {} exchanges of {} against the {} emulator at {}\n", exchanges.size(),
               options.file, family->label, describe(*settings));
    std::size_t differing = 0;
    for (const Exchange& exchange : exchanges) {
      const auto found = differences(exchange, ask(**port, exchange, sensor), sensor);
      if (!found.empty()) ++differing;
      for (const std::string& difference : found) fmt::print("  {}\n", difference);
    }
    fmt::print("{} of {} exchanges differ (distances compared by shape only)\n", differing, exchanges.size());
    code = differing == 0 ? exit_ok : exit_bad_input;
  }
  std::filesystem::remove_all(dir);
  return code;
}

}  // namespace

CLI::App* add_tap_compare_command(CLI::App& tap, int& exit_code) {
  auto options = std::make_shared<CompareOptions>();
  auto* compare = tap.add_subcommand(
      "compare", "Send a recording's requests to the family's emulator and show where its answers differ");
  compare->add_option("file", options->file, "the recording (.pcapng, as tap --out writes it)")->required();
  compare->add_option("--family", options->family, "when the recording does not name it: " + cli_family_names(" | "));
  compare->footer(
      "Exit codes: 0 no difference, 3 some exchanges differ or the recording is damaged, 4 the file "
      "cannot be read or the emulator not started.");
  compare->callback([options, &exit_code] { exit_code = run_compare(*options); });
  return compare;
}

}  // namespace rangekit::cli
