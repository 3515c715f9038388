// `rangekit demo`: the main job. Live by default (an emulator of each family streamed
// and captured); `--walkthrough` decodes a sample session typed from the documents.
#pragma once

#include <functional>
#include <span>
#include <string>
#include <string_view>

#include "cli/describe.hpp"

namespace rangekit::cli {

int run_walkthrough();

// One line of a walkthrough session: who sent it, the bytes without the CR, where the document says so.
struct WalkthroughLine {
  Direction direction;
  std::string_view wire;
  std::string_view source;
};
using FrameDescriber = std::function<std::string(Bytes frame, Direction direction)>;
// Prints the session under its title, each line decoded by `describe`.
void print_walkthrough_session(std::string_view title, std::span<const WalkthroughLine> lines,
                               const FrameDescriber& describe);

}  // namespace rangekit::cli
