// Shared pieces of the decoder corpus tests: a portable random source, byte mutations
// that make good lines malformed, and a digest of everything the decoders output, which
// must match the unoptimised decoders' (commit 3310b0b), values and messages alike.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <string_view>

#include "rangekit/core/framer.hpp"

namespace rangekit::testing::corpus {

// splitmix64: the same sequence on every platform and standard library (the
// std:: distributions are implementation-defined, so they would not be).
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31U);
  }
  // 0 .. bound-1
  std::uint32_t below(std::uint32_t bound) { return static_cast<std::uint32_t>(next() % bound); }
  bool one_in(std::uint32_t n) { return below(n) == 0; }

 private:
  std::uint64_t state_;
};

// Bytes that matter to the framers and field parsers, and a few that do not.
inline constexpr char interesting_chars[] = "$#!%,.-+0123456789ABEFMRabz \r\n\t\x00\x7f\x80\xff";
inline constexpr std::string_view interesting_bytes{interesting_chars, sizeof interesting_chars - 1};

// One damaging edit of a line: a byte replaced, deleted, inserted or repeated,
// the line cut short, or a field doubled.
inline std::string mutate(std::string line, Random& random) {
  if (line.empty()) return line;
  const auto at = static_cast<std::size_t>(random.below(static_cast<std::uint32_t>(line.size())));
  const char byte = random.one_in(4)
                        ? static_cast<char>(random.below(256))
                        : interesting_bytes[random.below(static_cast<std::uint32_t>(interesting_bytes.size()))];
  switch (random.below(6)) {
    case 0:
      line[at] = byte;
      break;
    case 1:
      line.erase(at, 1);
      break;
    case 2:
      line.insert(at, 1, byte);
      break;
    case 3:
      line.insert(at, line.substr(at, 1 + random.below(4)));
      break;
    case 4:
      line.resize(at);
      break;
    default: {
      const std::size_t comma = line.rfind(',');
      if (comma != std::string::npos) line.insert(comma, line.substr(comma, line.size() - comma - 1));
      break;
    }
  }
  return line;
}

// FNV-1a over every output line, and the line count.
class Digest {
 public:
  explicit Digest(std::string name) : name_(std::move(name)) {
    if (const char* dir = std::getenv("RANGEKIT_DECODER_CORPUS_DUMP"))
      dump_.open(std::string(dir) + "/" + name_ + ".txt");
  }
  void add(std::string_view line) {
    for (const char c : line) mix(static_cast<std::uint8_t>(c));
    mix('\n');
    ++lines_;
    if (dump_.is_open()) dump_ << line << '\n';
  }
  [[nodiscard]] std::uint64_t value() const { return hash_; }
  [[nodiscard]] std::size_t lines() const { return lines_; }
  [[nodiscard]] std::string hex() const {
    char text[24];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash_));
    return text;
  }

 private:
  void mix(std::uint8_t byte) {
    hash_ ^= byte;
    hash_ *= 0x100000001B3ULL;
  }
  std::string name_;
  std::uint64_t hash_ = 0xCBF29CE484222325ULL;
  std::size_t lines_ = 0;
  std::ofstream dump_;
};

// A double exactly (17 significant digits round-trip).
inline std::string exact(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

// Bytes as printable text for the dump: \xNN for the rest.
inline std::string escaped(std::string_view bytes) {
  std::string text;
  for (const char c : bytes) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7F && byte != '\\') {
      text += c;
    } else {
      char code[8];
      std::snprintf(code, sizeof code, "\\x%02X", byte);
      text += code;
    }
  }
  return text;
}

// The corpus as one stream: `lines` lines of make_line(random), one in four damaged by mutate.
template <class MakeLine>
std::string corpus_stream(Random& random, std::size_t lines, MakeLine make_line) {
  std::string stream;
  for (std::size_t i = 0; i < lines; ++i) {
    std::string line = make_line(random);
    if (random.one_in(4)) line = mutate(std::move(line), random);
    stream += line;
  }
  return stream;
}

// Feeds `stream` to an assembler in random chunks of 1-200 bytes, as reads arrive, and
// calls drain(assembler) after each.
template <class Drain>
void feed_in_chunks(std::string_view stream, ScanFunction scan, Random& random, Drain drain) {
  FrameAssembler assembler(scan, 256);
  std::size_t offset = 0;
  while (offset < stream.size()) {
    const std::size_t chunk = std::min<std::size_t>(1 + random.below(200), stream.size() - offset);
    offset += assembler.push(as_bytes(stream.substr(offset, chunk)));
    drain(assembler);
  }
}

// The lines of the framing digest.
inline void add_rejection(Digest& framing, const FrameAssembler::Event& event) {
  framing.add("rejected " + std::to_string(event.rejected_bytes) + " " + event.reason);
}
inline void add_frame(Digest& framing, Bytes frame) { framing.add("frame " + escaped(as_text(frame))); }

// Feeds `stream` to a framer in random chunks of 1-200 bytes, as reads arrive, records each
// rejection and frame in `framing`, and hands every frame to on_frame.
template <class OnFrame>
void frame_in_chunks(std::string_view stream, ScanFunction scan, Random& random, Digest& framing, OnFrame on_frame) {
  feed_in_chunks(stream, scan, random, [&](FrameAssembler& assembler) {
    FrameAssembler::Event event;
    while (assembler.next(event)) {
      if (event.kind == FrameAssembler::Event::Kind::rejected) {
        add_rejection(framing, event);
        continue;
      }
      add_frame(framing, event.frame);
      on_frame(event.frame);
    }
  });
}

}  // namespace rangekit::testing::corpus
