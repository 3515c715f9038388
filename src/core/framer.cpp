#include "rangekit/core/framer.hpp"

#include <algorithm>

namespace rangekit {
namespace {

bool is_start(std::uint8_t byte, std::string_view starts) noexcept {
  for (const char start : starts) {
    if (static_cast<std::uint8_t>(start) == byte) return true;
  }
  return false;
}

}  // namespace

FrameScan scan_line_frame(Bytes buffer, const LineFramerRules& rules) noexcept {
  if (buffer.empty()) return FrameScan::need_more();

  // Line endings between frames are not an error; anything else before a start byte is.
  std::size_t lead = 0;
  while (lead < buffer.size() && (buffer[lead] == '\r' || buffer[lead] == '\n')) ++lead;
  if (lead > 0) return FrameScan::invalid(lead, nullptr);  // silent drop: reason null
  if (!is_start(buffer[0], rules.starts)) {
    std::size_t skip = 1;
    while (skip < buffer.size() && !is_start(buffer[skip], rules.starts)) ++skip;
    return FrameScan::invalid(skip, "bytes before the start of a frame");
  }

  // One pass finds the terminator and checks the bytes before it, in order, so the
  // first problem in the frame is the one reported. Frames are a few dozen bytes:
  // a plain loop beats a memchr call plus a second pass.
  const std::size_t window = std::min(buffer.size(), rules.max_length + 1);
  // Bytes above every start character and below DEL need no further look: the
  // common case (digits, letters, ',' and '.' all sit above '$', '#', '!', '%').
  std::uint8_t highest_start = 0;
  for (const char start : rules.starts) highest_start = std::max(highest_start, static_cast<std::uint8_t>(start));
  const std::uint8_t plain_from = std::max<std::uint8_t>(0x20, static_cast<std::uint8_t>(highest_start + 1));
  std::size_t end = 1;
  bool terminated = false;
  for (; end < window; ++end) {
    const std::uint8_t byte = buffer[end];
    if (byte == rules.terminator) {
      terminated = true;
      break;
    }
    if (byte >= plain_from && byte < 0x7f) continue;
    if (byte >= 0x20 && byte < 0x7f && !is_start(byte, rules.starts)) continue;
    if (rules.allow_high_bytes_at && end == rules.high_byte_position)
      continue;  // any address byte; the codec checks it
    if (is_start(byte, rules.starts)) return FrameScan::invalid(end, "frame cut short by a new start byte");
    if (byte == '\n') return FrameScan::invalid(end + 1, "line feed inside a frame (frames end with CR)");
    return FrameScan::invalid(end + 1, "control or non-ASCII byte inside a frame");
  }
  if (terminated) {
    if (end > rules.max_length) return FrameScan::invalid(end + 1, "frame longer than the protocol allows");
    return FrameScan::complete(buffer.first(end), end + 1);
  }
  if (end > rules.max_length) return FrameScan::invalid(rules.max_length, "frame longer than the protocol allows");
  return FrameScan::need_more();
}

}  // namespace rangekit

namespace rangekit {

FrameAssembler::FrameAssembler(ScanFunction scan, std::size_t capacity) : scan_(scan), buffer_(capacity) {}

std::size_t FrameAssembler::push(Bytes bytes) {
  if (begin_ > 0 && buffer_.size() - end_ < bytes.size()) {
    std::copy(buffer_.begin() + static_cast<std::ptrdiff_t>(begin_),
              buffer_.begin() + static_cast<std::ptrdiff_t>(end_), buffer_.begin());
    end_ -= begin_;
    begin_ = 0;
  }
  const std::size_t room = buffer_.size() - end_;
  const std::size_t taken = bytes.size() < room ? bytes.size() : room;
  std::copy_n(bytes.begin(), taken, buffer_.begin() + static_cast<std::ptrdiff_t>(end_));
  end_ += taken;
  return taken;
}

bool FrameAssembler::next(Event& event) {
  while (begin_ < end_) {
    const Bytes pending(buffer_.data() + begin_, end_ - begin_);
    const FrameScan scan = scan_(pending);
    if (scan.status == FrameStatus::need_more) {
      if (pending.size() < buffer_.size()) return false;
      // A full buffer with no frame end can never complete: reject it whole.
      begin_ = end_ = 0;
      event = Event{Event::Kind::rejected, {}, pending.size(), "buffer full without a frame end"};
      return true;
    }
    begin_ += scan.consumed;
    if (scan.status == FrameStatus::complete) {
      event = Event{Event::Kind::frame, scan.frame, 0, nullptr};
      return true;
    }
    if (!scan.benign()) {
      event = Event{Event::Kind::rejected, {}, scan.consumed, scan.reason};
      return true;
    }
  }
  begin_ = end_ = 0;
  return false;
}

}  // namespace rangekit
