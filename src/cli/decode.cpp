// `rangekit decode`: reads raw protocol bytes (a capture, a terminal log, stdin)
// and prints each frame decoded, or why bytes were rejected.
#include <fmt/core.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>

#include "cli/commands.hpp"
#include "cli/describe.hpp"
#include "rangekit/ls5/frame.hpp"
#include "rangekit/uls/frame.hpp"

namespace rangekit::cli {
namespace {

struct DecodeOptions {
  std::string family;
  std::string file;
  std::string from = "device";
  std::string mode = "averaging";
  std::string display = "range";
  std::string units = "m";
  bool time_between_events = false;
  double range_mm = 0;
};

uls::MeasurementContext context_of(const DecodeOptions& options) {
  static const std::map<std::string, uls::Mode> modes{
      {"averaging", uls::Mode::averaging}, {"binning", uls::Mode::binning}, {"look-down", uls::Mode::look_down}};
  static const std::map<std::string, uls::DisplayMode> displays{{"range", uls::DisplayMode::range},
                                                                {"both", uls::DisplayMode::range_and_intensity},
                                                                {"intensity", uls::DisplayMode::intensity}};
  return uls::MeasurementContext{modes.at(options.mode), displays.at(options.display),
                                 options.units == "ft" ? uls::Units::feet : uls::Units::metres,
                                 options.time_between_events};
}

int run_decode(const DecodeOptions& options) {
  std::string bytes;
  if (options.file.empty() || options.file == "-") {
    bytes.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
  } else {
    std::ifstream in(options.file, std::ios::binary);
    if (!in) {
      fmt::print(stderr, "rangekit decode: cannot open {}\n", options.file);
      return exit_io;
    }
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const bool uls = options.family == "uls";
  const Direction direction = options.from == "host" ? Direction::to_device : Direction::from_device;
  ScanFunction scan =
      uls ? &uls::scan_frame : (direction == Direction::to_device ? &ls5::scan_request_frame : &ls5::scan_reply_frame);
  const auto context = context_of(options);
  FrameAssembler assembler(scan, 4096);
  FrameAssembler::Event event;
  int frames = 0;
  int rejected = 0;
  auto drain = [&] {
    while (assembler.next(event)) {
      if (event.kind == FrameAssembler::Event::Kind::rejected) {
        ++rejected;
        fmt::print("!! {} byte(s) rejected: {}\n", event.rejected_bytes, event.reason);
        continue;
      }
      ++frames;
      const std::string description = uls ? describe_uls_frame(event.frame, direction, context)
                                          : describe_ls5_frame(event.frame, direction, options.range_mm);
      if (description.rfind("rejected", 0) == 0 || description.rfind("not a", 0) == 0) ++rejected;
      fmt::print("{:<24} {}\n", printable(event.frame), description);
    }
  };
  for (std::size_t offset = 0; offset < bytes.size(); offset += 1024) {
    assembler.push(as_bytes(std::string_view(bytes).substr(offset, 1024)));
    drain();
  }
  if (assembler.buffered() > 0) {
    ++rejected;
    fmt::print("!! {} byte(s) at the end without a terminating CR\n", assembler.buffered());
  }
  fmt::print(stderr, "{} frame(s), {} problem(s)\n", frames, rejected);
  return rejected == 0 ? exit_ok : exit_bad_input;
}

}  // namespace

void add_decode_command(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<DecodeOptions>();
  auto* command = app.add_subcommand("decode", "Decode ULS or LS5 frames from a file or stdin");
  command->add_option("family", options->family, "uls | ls5")->required()->check(CLI::IsMember({"uls", "ls5"}));
  command->add_option("file", options->file, "file of raw bytes (default: stdin)");
  command->add_option("--from", options->from, "who sent the bytes: device (replies, measurements) or host (commands)")
      ->check(CLI::IsMember({"device", "host"}));
  command->add_option("--mode", options->mode, "ULS measurement mode the BM lines come from")
      ->check(CLI::IsMember({"averaging", "binning", "look-down"}));
  command->add_option("--display", options->display, "ULS averaging display mode (DM)")
      ->check(CLI::IsMember({"range", "both", "intensity"}));
  command->add_option("--units", options->units, "ULS units (MU)")->check(CLI::IsMember({"m", "ft"}));
  command->add_flag("--time-between-events", options->time_between_events, "ULS look down with TB on");
  command->add_option("--range-mm", options->range_mm, "LS5 measurement range, to print millimetres")
      ->check(range_millimetres());
  command->footer("Exit codes: 0 every frame decoded, 3 some bytes or frames rejected, 4 file not readable.");
  command->callback([options, &exit_code] { exit_code = run_decode(*options); });
}

}  // namespace rangekit::cli
