// A sensor family as the rangekit binary sees it: its subcommand, its emulator and its part of
// the generic commands (decode, tables, detect, capture, the demos). Each family fills one in
// its own folder (src/<family>/cli); the registration list adds it before main().
#pragma once

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cli/demo_site.hpp"
#include "cli/describe.hpp"
#include "rangekit/core/channel.hpp"
#include "rangekit/core/framer.hpp"
#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/core/transport.hpp"
#include "rangekit/sim/motion.hpp"

namespace rangekit::cli {

// How `rangekit decode` reads the bytes one side sent: the framer and the words for a frame.
struct FrameDecoder {
  ScanFunction scan = nullptr;
  std::function<std::string(Bytes frame)> describe;
  // Whether a frame's values come from the target (a distance) rather than the unit's state
  // (a setting, an error number): `tap compare` compares those by shape only. None: never.
  std::function<bool(Bytes frame)> measured;
  // Whether the frame is a message of this family (a known command, reply or record), not only
  // bytes its framer delimits: how `tap` tells the family from the traffic.
  std::function<bool(Bytes frame)> known;
};
// One side of a conversation being read: its decoder and the bytes of its unfinished frame.
struct DecodingSide {
  FrameDecoder decoder;
  FrameAssembler assembler;
  explicit DecodingSide(FrameDecoder d) : decoder(std::move(d)), assembler(decoder.scan, 4096) {}
};
// Built once the command line is parsed, for the side that sent the bytes.
using DecoderFactory = std::function<FrameDecoder(Direction sender)>;

// One of `rangekit tables`, named "<family>-<name>".
struct CliTable {
  std::string_view name;  // "commands"
  void (*print)(bool markdown) = nullptr;
};

// A sensor `rangekit detect` heard.
struct DetectFinding {
  std::string port;
  std::string family;
  std::uint32_t baud = 0;
  std::string address;
  std::string version;
  std::string detail;
  std::string byte_format = "8N1";
};
// Asks with read requests only, so a device is left as it was found; every sensor that answered.
using DetectProbe = std::function<std::vector<DetectFinding>(Transport& port, const std::string& path,
                                                             std::uint32_t baud, std::chrono::milliseconds timeout)>;

struct CliDetect {
  std::vector<std::uint32_t> (*bauds)() = nullptr;  // the rates its document lists
  bool other_byte_formats = false;                  // may answer in formats besides 8N1, at its own rates
  // Adds its options to `rangekit detect` (addresses to ask); the probe reads them once parsed.
  DetectProbe (*add_options)(CLI::App& detect) = nullptr;
};

// Starts a stream on each of the family's ports given to `rangekit capture`; none when none was.
using SourceStarter = std::function<Result<std::vector<SampleSourcePtr>>()>;

// Where the family's emulator of `rangekit demo` keeps its files, all in one directory.
struct DemoFiles {
  std::filesystem::path dir;
  std::string port;     // <dir>/<family>
  std::string scene;    // <dir>/<family>-scene.toml, written before the emulator starts
  std::string control;  // <dir>/<family>.control
};

struct CliDemo {
  const char* scene = nullptr;                                                  // the emulator's TOML scene
  std::vector<std::string> (*sim_arguments)(const DemoFiles& files) = nullptr;  // after `rangekit sim`
  // Sets the emulated sensor up, starts its stream and prints what it streams; an error's
  // message is printed as it is.
  Result<SampleSourcePtr> (*start_source)(const DemoFiles& files) = nullptr;
  const char* busy_output = nullptr;  // the emulator's `outputs` flag while it sends: "measuring"
  const char* idle_text = nullptr;    // what "Left as found" says when that flag is off
  // `demo --walkthrough`: a session typed from its document, decoded; an exit code.
  int (*walkthrough)() = nullptr;
};

// A sensor's readings out of a capture, for `sim replay` to have the emulator follow them.
struct CapturedReadings {
  const ChannelDescriptor* channel = nullptr;  // the readings' channel (its key and unit)
  std::vector<PathPoint> points;               // seconds from the first reading, the reading
};
// The family's emulator set up so that its target follows captured readings.
struct CaptureScene {
  std::vector<std::string> sim_arguments;  // after `sim <name>`, besides --port and --scene
  std::string scene;                       // the emulator's TOML scene
};

struct CliFamily {
  std::string_view name;   // its subcommand and its samples' `device`: the folder src/<name>
  std::string_view label;  // how help and messages name it
  void (*add_command)(CLI::App& app, int& exit_code) = nullptr;      // `rangekit <name> ...`
  void (*add_sim_command)(CLI::App& sim, int& exit_code) = nullptr;  // `rangekit sim <name>`
  DecoderFactory (*add_decode_options)(CLI::App& decode) = nullptr;
  std::span<const CliTable> tables;
  std::string_view default_max_speed;  // in words, for --max-speed's help
  CliDetect detect;
  SourceStarter (*add_capture_options)(CLI::App& capture) = nullptr;  // --<name> PORT and its settings
  CliDemo demo;
  CliDemoSite demo_site;
  // An error naming why when the emulator cannot follow these readings (another channel).
  Result<CaptureScene> (*capture_scene)(const CapturedReadings& readings) = nullptr;
};

// The family's decoders with its decode options at their defaults, for a command that reads
// frames without offering those options (sim replay, tap): one factory makes both sides', so
// that they share what the traffic teaches them (a setting read back).
DecoderFactory default_decoders(const CliFamily& family);
FrameDecoder default_decoder(const CliFamily& family, Direction sender);

// Adds a family (a second of the same name replaces the first); from the registration list.
void register_cli_family(const CliFamily& family);
// The registered families, in registration order: the order of the subcommands and of help texts.
std::span<const CliFamily* const> cli_families() noexcept;
const CliFamily* find_cli_family(std::string_view name) noexcept;

// The families' names or labels joined for help texts: "a | b", "A and B".
std::string cli_family_names(std::string_view separator);
std::string cli_family_labels(std::string_view separator);
std::vector<std::string> cli_family_name_list();
// "both" with two families, else "all"; a small count in words ("two").
std::string_view both_or_all();
std::string count_in_words(std::size_t count);

}  // namespace rangekit::cli
