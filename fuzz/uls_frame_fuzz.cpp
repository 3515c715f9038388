// Fuzzes the ULS receive path: bytes -> FrameAssembler(scan_frame) -> parse_frame
// -> decode_reply and decode_measurement. A decoded measurement must re-encode to a
// line that decodes to the same reading.
#include <array>
#include <cstddef>
#include <cstdint>

#include "rangekit/uls/uls.hpp"

namespace {

using namespace rangekit;
using namespace rangekit::uls;

std::array<MeasurementContext, 36> all_contexts() {
  std::array<MeasurementContext, 36> contexts{};
  std::size_t i = 0;
  for (const Mode mode : {Mode::averaging, Mode::binning, Mode::look_down}) {
    for (const DisplayMode display : {DisplayMode::range, DisplayMode::range_and_intensity, DisplayMode::intensity}) {
      for (const Units units : {Units::feet, Units::metres}) {
        for (const bool events : {false, true}) contexts[i++] = {mode, display, units, events};
      }
    }
  }
  return contexts;
}

const std::array<MeasurementContext, 36> contexts = all_contexts();

void check_measurement(const FrameView& view, const MeasurementContext& context) {
  const Result<Measurement> decoded = decode_measurement(view, context);
  if (!decoded) {
    if (decoded.error().message.empty()) __builtin_trap();
    return;
  }
  const Result<FrameText> line = encode_measurement(decoded->source, decoded->reading);
  if (!line) __builtin_trap();  // whatever decodes must be writable
  const Result<Measurement> again = decode_measurement(as_bytes(line->frame()), context);
  if (!again || !(again->reading == decoded->reading) || !(again->source == decoded->source)) __builtin_trap();
}

void check_frame(Bytes frame, const MeasurementContext& context) {
  const Result<FrameView> view = parse_frame(frame);
  if (!view) {
    if (view.error().message.empty()) __builtin_trap();
    return;
  }
  for (const Units units : {Units::feet, Units::metres}) {
    const Result<Reply> reply = decode_reply(*view, units);
    if (!reply && reply.error().message.empty()) __builtin_trap();
  }
  check_measurement(*view, context);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static FrameAssembler assembler(scan_frame, 256);
  assembler.clear();
  // The first byte picks the chunk size, so split deliveries are exercised too.
  const std::size_t chunk = size == 0 ? 1 : 1 + data[0] % 16;
  const Bytes input(data, size);
  std::size_t frames = 0;
  for (std::size_t at = 0; at < size; at += chunk) {
    assembler.push(input.subspan(at, std::min(chunk, size - at)));
    FrameAssembler::Event event;
    while (assembler.next(event)) {
      if (event.kind == FrameAssembler::Event::Kind::frame) {
        // One of the 36 contexts per frame, by length and place, so mutations reach every
        // context; all 36 per frame made this target 36 times slower than the others.
        check_frame(event.frame, contexts[(size + frames++) % contexts.size()]);
      } else if (event.reason == nullptr) {
        __builtin_trap();  // every rejection carries its reason
      }
    }
  }
  // The whole input as one line, too.
  const Result<FrameView> whole = parse_wire_frame(input);
  if (!whole && whole.error().message.empty()) __builtin_trap();
  return 0;
}
