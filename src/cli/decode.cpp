// `rangekit decode`: reads raw protocol bytes (a capture, a terminal log, stdin)
// and prints each frame decoded, or why bytes were rejected.
#include <fmt/core.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>

#include "cli/cli_family.hpp"
#include "cli/commands.hpp"
#include "cli/describe.hpp"

namespace rangekit::cli {
namespace {

struct DecodeOptions {
  std::string file;
  std::string from = "device";
};

int run_decode(const DecodeOptions& options, const DecoderFactory& decoder_of) {
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
  const Direction direction = options.from == "host" ? Direction::to_device : Direction::from_device;
  const FrameDecoder decoder = decoder_of(direction);
  FrameAssembler assembler(decoder.scan, 4096);
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
      const std::string description = decoder.describe(event.frame);
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
  auto* command = app.add_subcommand("decode", "Decode " + cli_family_labels(" or ") + " frames from a file or stdin");
  command->require_subcommand(1);
  // `decode FAMILY`: a subcommand each, so that a family's options (--mode, --range-mm) are its own
  // and two families may have one of the same name. --from is taken before the family or after.
  const auto add_from = [&options](CLI::App& to) {
    to.add_option("--from", options->from, "who sent the bytes: device (replies, measurements) or host (commands)")
        ->check(CLI::IsMember({"device", "host"}));
  };
  add_from(*command);
  command->footer("Exit codes: 0 every frame decoded, 3 some bytes or frames rejected, 4 file not readable.");
  for (const CliFamily* family : cli_families()) {
    auto* decode =
        command->add_subcommand(std::string(family->name), "Decode " + std::string(family->label) + " frames");
    decode->add_option("file", options->file, "file of raw bytes (default: stdin)");
    add_from(*decode);
    decode->callback([options, decoder_of = family->add_decode_options(*decode), &exit_code] {
      exit_code = run_decode(*options, decoder_of);
    });
  }
}

}  // namespace rangekit::cli
