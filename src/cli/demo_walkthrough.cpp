// `rangekit demo --walkthrough`: a sample session typed from each family's document,
// both directions, decoded through the same codecs the drivers use.
#include <fmt/core.h>

#include "cli/cli_family.hpp"
#include "cli/commands.hpp"
#include "cli/demo.hpp"

namespace rangekit::cli {

void print_walkthrough_session(std::string_view title, std::span<const WalkthroughLine> lines,
                               const FrameDescriber& describe) {
  fmt::print("\n{}\n", title);
  for (const auto& line : lines) {
    const std::string description = describe(as_bytes(line.wire), line.direction);
    fmt::print("  {} {:<40} {}\n", line.direction == Direction::to_device ? "host ->" : "     <-", line.wire,
               description);
    fmt::print("          {:<40} ({})\n", "", line.source);
  }
}

int run_walkthrough() {
  fmt::print("rangekit demo --walkthrough: a sample session typed from the {} documents, decoded by the codecs.\n",
             count_in_words(cli_families().size()));
  for (const CliFamily* family : cli_families()) {
    if (family->demo.walkthrough == nullptr) continue;
    if (const int code = family->demo.walkthrough(); code != exit_ok) return code;
  }
  return exit_ok;
}

}  // namespace rangekit::cli
