// Which family a tapped conversation is in, told from its frames: every family's decoders
// read the same chunks, and a family is named once it has understood several frames while
// every other family's framer and decoder keep failing on them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "cli/cli_family.hpp"
#include "rangekit/core/framer.hpp"
#include "rangekit/record/pcapng.hpp"

namespace rangekit::cli {

class FamilyGuess {
 public:
  // Frames a family must understand, and its lead over the next, before it is named.
  static constexpr int frames_to_decide = 3;

  explicit FamilyGuess(std::span<const CliFamily* const> families);
  // The family once the chunks read so far decide it; null until then.
  const CliFamily* add(const record::SerialChunk& chunk);
  // What was heard, for a tap that ends undecided: "ULS 1 frame understood, 4 not; LS5 ...".
  [[nodiscard]] std::string summary() const;

 private:
  struct Candidate {
    const CliFamily* family;
    DecodingSide host;
    DecodingSide sensor;
    int understood = 0;
    int failed = 0;  // frames not understood and runs of bytes its framer rejected
    [[nodiscard]] int score() const noexcept { return understood - 2 * failed; }
  };
  std::vector<Candidate> candidates_;
};

}  // namespace rangekit::cli
