// Framing: finding frame boundaries in a byte stream, without I/O.
//
// A framer looks at the front of a buffer and answers one of three ways, as in
// libsigrok's packet parsers: a complete frame is there, more bytes are needed,
// or the front bytes are not a frame and must be dropped.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace rangekit {

using Bytes = std::span<const std::uint8_t>;

enum class FrameStatus { complete, need_more, invalid };

struct FrameScan {
  FrameStatus status = FrameStatus::need_more;
  // Bytes the caller drops from the front of its buffer: the frame and its
  // terminator when complete, the rejected bytes when invalid, 0 when more are needed.
  std::size_t consumed = 0;
  // The frame without its terminator (complete only); points into the scanned buffer.
  Bytes frame{};
  // Why the bytes were rejected (invalid only); a static string, no allocation.
  // Null for benign separators (CR/LF between frames).
  const char* reason = nullptr;

  // Line endings between frames: dropped without complaint.
  [[nodiscard]] bool benign() const noexcept { return status == FrameStatus::invalid && reason == nullptr; }

  static FrameScan complete(Bytes frame, std::size_t consumed) {
    return FrameScan{FrameStatus::complete, consumed, frame, nullptr};
  }
  static FrameScan need_more() { return FrameScan{}; }
  static FrameScan invalid(std::size_t consumed, const char* why) {
    return FrameScan{FrameStatus::invalid, consumed, {}, why};
  }
};

inline std::string_view as_text(Bytes bytes) { return {reinterpret_cast<const char*>(bytes.data()), bytes.size()}; }
inline Bytes as_bytes(std::string_view text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

// Configuration of a line framer: frames begin with one of `starts` and end with
// `terminator`; frames longer than `max_length` bytes (start byte included,
// terminator excluded) are invalid.
struct LineFramerRules {
  std::string_view starts;  // e.g. "$#" for ULS
  std::uint8_t terminator = '\r';
  std::size_t max_length = 64;
  bool allow_high_bytes_at = false;    // see `high_byte_position`
  std::size_t high_byte_position = 0;  // a byte >= 0x80 is allowed only at this offset (ULS address)
};

// Generic start-byte/terminator framer shared by both protocols.
//  - CR and LF between frames are dropped silently (terminal line endings);
//  - any other byte before a start byte is rejected as garbage;
//  - a start byte inside a frame means the earlier frame was cut short: it is
//    rejected and scanning resumes at the new start byte;
//  - control bytes (NUL, LF, ...) inside a frame make it invalid.
FrameScan scan_line_frame(Bytes buffer, const LineFramerRules& rules) noexcept;

using ScanFunction = FrameScan (*)(Bytes) noexcept;

// Accumulates bytes from a stream and hands out frames found by a scan function.
// Fixed capacity, no allocation after construction; a frame view stays valid
// until the next call to push() or next().
class FrameAssembler {
 public:
  struct Event {
    enum class Kind { frame, rejected } kind = Kind::frame;
    Bytes frame{};                   // kind == frame
    std::size_t rejected_bytes = 0;  // kind == rejected
    const char* reason = nullptr;    // kind == rejected
  };

  explicit FrameAssembler(ScanFunction scan, std::size_t capacity = 4096);

  // Appends bytes; returns how many were taken (fewer only when the buffer is
  // full of an unfinished frame, which the next call to next() rejects).
  std::size_t push(Bytes bytes);
  // Next frame or rejection; false when more bytes are needed.
  bool next(Event& event);
  [[nodiscard]] std::size_t buffered() const noexcept { return end_ - begin_; }
  // The bytes not handed out yet, and dropping `count` of them from the front: for a
  // decoder that reads the frames it knows best straight from the buffer instead of
  // one next() per frame (ls5::decode_replies). next() then carries on after them.
  [[nodiscard]] Bytes pending() const noexcept { return {buffer_.data() + begin_, end_ - begin_}; }
  void consume(std::size_t count) noexcept { begin_ += count < end_ - begin_ ? count : end_ - begin_; }
  void clear() noexcept { begin_ = end_ = 0; }

 private:
  ScanFunction scan_;
  std::vector<std::uint8_t> buffer_;
  std::size_t begin_ = 0;
  std::size_t end_ = 0;
};

// Feeds all of `bytes`, letting `drain` take frames (next(), or pending()/consume())
// whenever the buffer is full: a read as large as the capacity on top of a half frame
// already held loses nothing (push() takes only what fits).
template <class Drain>
void feed_all(FrameAssembler& assembler, Bytes bytes, Drain&& drain) {
  for (;;) {
    bytes = bytes.subspan(assembler.push(bytes));
    drain();
    if (bytes.empty()) return;
  }
}

}  // namespace rangekit
