// Measurement output lines (§8 "Measurement Data Output Formats", §9 "Output
// Serial Data Stream"). A BM line cannot be read without knowing the unit's
// settings (U11), so the decoder takes them as context.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <variant>

#include "rangekit/core/framer.hpp"
#include "rangekit/core/result.hpp"
#include "rangekit/uls/frame.hpp"
#include "rangekit/uls/types.hpp"

namespace rangekit::uls {

struct MeasurementContext {
  Mode mode = Mode::averaging;               // MM
  DisplayMode display = DisplayMode::range;  // DM (averaging only)
  Units units = Units::metres;               // MU
  bool time_between_events = false;          // TB (look down only)
  friend bool operator==(const MeasurementContext&, const MeasurementContext&) = default;
};

// §9 field widths (U27): a range is at most 8 characters with its sign, a pulse
// width at most 7 digits, so "$BM,xxxx.xxx" is 12 characters and
// "$BM,xxxx.xxx,yyyyyyy<CR>" 21.
inline constexpr std::size_t max_range_chars = 8;
inline constexpr std::size_t max_pulse_width_digits = 7;
inline constexpr std::size_t max_strength_digits = 5;
inline constexpr std::uint8_t max_binning_targets = 15;  // §3, §9

// A distance as sent, in user units, and the same in metres.
struct Range {
  double user = 0;  // feet or metres, as on the wire
  double metres = 0;
  Units units = Units::metres;
  friend bool operator==(const Range&, const Range&) = default;
};
// The Range for a value in user units.
Range make_range(double user_value, Units units) noexcept;

// Averaging: range, pulse width, or both (DM, U8, U9).
struct AveragingReading {
  std::optional<Range> range;
  std::optional<std::uint32_t> pulse_width_ps;  // picoseconds on the wire (U8)
  [[nodiscard]] std::optional<double> pulse_width_ns() const noexcept {
    if (!pulse_width_ps) return std::nullopt;
    return static_cast<double>(*pulse_width_ps) / 1000.0;
  }
  friend bool operator==(const AveragingReading&, const AveragingReading&) = default;
};

// Binning: one line per target, `$BM,i,m,n,s` (U10).
struct BinningTarget {
  std::uint8_t index = 0;  // 0-based position in the target array
  std::uint8_t count = 0;  // targets in the array, 1-15
  Range range;
  std::uint32_t strength = 0;  // hits in the target's bin
  friend bool operator==(const BinningTarget&, const BinningTarget&) = default;
};

// Look down without time between events: `$BM,0` / `$BM,1`.
struct LookDownReading {
  bool present = false;
  friend bool operator==(const LookDownReading&, const LookDownReading&) = default;
};

// A measurement error in the stream: `$ER,4`, `$ER,5` (U13).
struct MeasurementError {
  int number = 0;
  friend bool operator==(const MeasurementError&, const MeasurementError&) = default;
};

using Reading = std::variant<AveragingReading, BinningTarget, LookDownReading, TimeBetweenEvents, MeasurementError>;

struct Measurement {
  Address source;
  Reading reading;
};

// Reads one measurement line; does not allocate on success.
Result<Measurement> decode_measurement(const FrameView& frame, const MeasurementContext& context);
Result<Measurement> decode_measurement(Bytes frame, const MeasurementContext& context);

namespace detail {

// The line an averaging unit streams, "$BM,<range>[,<pulse width>]<CR>" or the same
// from a unit address "#a" (§9, U8, U9, U27), at the front of `pending`: its length
// with the CR, and the measurement decode_measurement gives for it in `out`; 0 for
// anything else (other modes and lines, a line not complete yet), which
// decode_measurement reads (or refuses, naming the problem) in full. Only lines of
// bytes scan_frame hands out whole as that frame are taken.
std::size_t read_good_averaging_line(Bytes pending, const MeasurementContext& context, Measurement& out);

}  // namespace detail

// Hands out every frame `assembler` holds, in order, as a stream reader needs them: a
// good averaging line to on_measurement(Bytes frame, const Measurement&), read straight
// from the assembler's buffer with no scan call, FrameView or Result built;
// any other frame to on_frame(Bytes frame), for the caller to read with parse_frame or
// decode_measurement exactly as before; rejected bytes to
// on_rejected(const FrameAssembler::Event&). The same frames and rejections, in the
// same order, as next() on every frame; the measurement is the one
// decode_measurement(frame, context) gives. Views are valid until the next push().
template <class OnMeasurement, class OnFrame, class OnRejected>
void decode_measurements(FrameAssembler& assembler, const MeasurementContext& context, OnMeasurement&& on_measurement,
                         OnFrame&& on_frame, OnRejected&& on_rejected) {
  FrameAssembler::Event event;
  Measurement measurement;
  while (true) {
    // Each line is consumed before its callback, as next() does: a callback that
    // clears the assembler (a new transport) ends the loop as it ends next().
    while (context.mode == Mode::averaging) {
      const Bytes pending = assembler.pending();
      const std::size_t length = detail::read_good_averaging_line(pending, context, measurement);
      if (length == 0) break;
      assembler.consume(length);
      on_measurement(pending.first(length - 1), std::as_const(measurement));
    }
    if (!assembler.next(event)) return;
    if (event.kind == FrameAssembler::Event::Kind::rejected) {
      on_rejected(event);
    } else {
      on_frame(event.frame);
    }
  }
}

// Writes the line a unit sends for a reading. Ranges are written in their own
// units (3 decimals metres, 2 feet) and must fit the §9 width (U27).
Result<FrameText> encode_averaging(Address address, const AveragingReading& reading);
Result<FrameText> encode_binning_target(Address address, const BinningTarget& target);
Result<FrameText> encode_look_down(Address address, bool present);
Result<FrameText> encode_measurement_error(Address address, int error_number);
Result<FrameText> encode_measurement(Address address, const Reading& reading);

}  // namespace rangekit::uls
