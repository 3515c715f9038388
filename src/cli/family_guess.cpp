#include "cli/family_guess.hpp"

#include <fmt/core.h>

#include <algorithm>

namespace rangekit::cli {

FamilyGuess::FamilyGuess(std::span<const CliFamily* const> families) {
  candidates_.reserve(families.size());
  for (const CliFamily* family : families) {
    const DecoderFactory decoders = default_decoders(*family);
    candidates_.push_back(Candidate{family, DecodingSide(decoders(Direction::to_device)),
                                    DecodingSide(decoders(Direction::from_device))});
  }
}

const CliFamily* FamilyGuess::add(const record::SerialChunk& chunk) {
  for (Candidate& candidate : candidates_) {
    DecodingSide& side = chunk.sender == record::Sender::host ? candidate.host : candidate.sensor;
    FrameAssembler::Event event;
    feed_all(side.assembler, as_bytes(chunk.bytes), [&] {
      while (side.assembler.next(event)) {
        if (event.kind == FrameAssembler::Event::Kind::rejected) {
          candidate.failed += event.reason != nullptr ? 1 : 0;  // line endings say nothing
        } else if (side.decoder.known && side.decoder.known(event.frame)) {
          ++candidate.understood;
        } else {
          ++candidate.failed;
        }
      }
    });
  }
  if (candidates_.empty()) return nullptr;
  const auto best = std::max_element(candidates_.begin(), candidates_.end(),
                                     [](const Candidate& a, const Candidate& b) { return a.score() < b.score(); });
  if (best->understood < frames_to_decide) return nullptr;
  for (const Candidate& other : candidates_) {
    if (&other != &*best && best->score() - other.score() < frames_to_decide) return nullptr;
  }
  return best->family;
}

std::string FamilyGuess::summary() const {
  std::string out;
  for (const Candidate& candidate : candidates_) {
    out += fmt::format("{}{}: {} frame(s) understood, {} not", out.empty() ? "" : "; ", candidate.family->label,
                       candidate.understood, candidate.failed);
  }
  return out;
}

}  // namespace rangekit::cli
