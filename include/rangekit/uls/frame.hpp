// ULS frames (§8 "Message Format"): finding them in a byte stream, reading
// one into a view, and writing one into a fixed-capacity text object.
//
//   $CCCC[,v1,...]<CR>        non-addressable
//   #aCCCC[,v1,...]<CR>       addressable: a = one address byte 0x30-0xFF (U4)
//   $0 / $XXXX / #a0 / #aXXXX time between events (U12)
//
// Nothing here allocates on success; errors carry a message naming the problem.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "rangekit/core/framer.hpp"
#include "rangekit/core/result.hpp"
#include "rangekit/uls/types.hpp"

namespace rangekit::uls {

inline constexpr std::size_t max_frame_length = 64;    // bytes before the CR (F5)
inline constexpr std::size_t max_fields = 8;           // values after the mnemonic (U28)
inline constexpr std::size_t min_mnemonic_length = 2;  // "2 to 4-letter mnemonic" (§8)
inline constexpr std::size_t max_mnemonic_length = 4;

// Framer for a ULS byte stream (F1-F5): starts "$#", CR, 64 bytes; the address
// slot of '#' frames and the value byte of a UA set may hold any byte (U4, U25).
FrameScan scan_frame(Bytes buffer) noexcept;

enum class FrameKind { message, time_between_events };

// One parsed frame; the views point into the parsed bytes.
struct FrameView {
  FrameKind kind = FrameKind::message;
  Address address;            // addressed == ('#' frame)
  std::string_view mnemonic;  // as received (case kept); empty for time between events
  std::array<std::string_view, max_fields> field_slots{};
  std::size_t field_count = 0;
  std::string_view event_text;  // time between events: "0" or four hex digits

  [[nodiscard]] std::span<const std::string_view> fields() const noexcept { return {field_slots.data(), field_count}; }
  // Case-insensitive comparison with an upper-case mnemonic (U17).
  [[nodiscard]] bool is(std::string_view upper_mnemonic) const noexcept;
};

// Parses one frame without its CR (as scan_frame hands it out).
Result<FrameView> parse_frame(Bytes frame);
Result<FrameView> parse_frame(std::string_view frame);
// Parses bytes that must hold exactly one frame and its CR: for single lines
// (tests, a terminal line); a missing CR is `truncated`, framer rejections keep their reason.
Result<FrameView> parse_wire_frame(Bytes wire);

// Fixed-capacity text of one frame including its CR.
class FrameText {
 public:
  static constexpr std::size_t capacity = max_frame_length + 1;

  [[nodiscard]] std::string_view wire() const noexcept { return {data_.data(), size_}; }
  [[nodiscard]] std::string_view frame() const noexcept {  // without the CR
    return {data_.data(), size_ == 0 ? 0 : size_ - 1};
  }
  [[nodiscard]] Bytes bytes() const noexcept { return as_bytes(wire()); }
  [[nodiscard]] std::size_t size() const noexcept { return size_; }

  // Building blocks for the encoders; false when the frame would be too long.
  bool append(std::string_view text) noexcept;
  bool append(char c) noexcept;

 private:
  std::array<char, capacity> data_{};
  std::size_t size_ = 0;
};

// Fixed-capacity text of one value, for building fields without allocation.
struct FieldText {
  std::array<char, 24> chars{};
  std::size_t size = 0;
  [[nodiscard]] std::string_view view() const noexcept { return {chars.data(), size}; }
};
FieldText format_unsigned(std::uint64_t value) noexcept;
// A distance as the ULS writes it: 3 decimals in metres, 2 in feet (§9, U9),
// rounded to the nearest step; none when not finite or beyond 12 integer digits.
std::optional<FieldText> format_distance(double value, Units units) noexcept;

// Any frame: start, address, mnemonic (written upper case, U17), fields.
// Refuses what parse_frame would refuse: bad address, mnemonic, field bytes,
// too many fields, frame over 64 bytes.
Result<FrameText> encode_frame(Address address, std::string_view mnemonic,
                               std::span<const std::string_view> fields = {});

// Requests (§8): get and action carry no values (BR's get carries the port).
Result<FrameText> encode_get(Address address, std::string_view mnemonic,
                             std::span<const std::string_view> arguments = {});
Result<FrameText> encode_action(Address address, std::string_view mnemonic);
Result<FrameText> encode_set(Address address, std::string_view mnemonic, std::span<const std::string_view> values);
Result<FrameText> encode_set(Address address, std::string_view mnemonic, std::uint64_t value);

// Replies (§8): $OK, $ER,n, $CC,values.
Result<FrameText> encode_ok(Address address);
Result<FrameText> encode_error_reply(Address address, int error_number);
Result<FrameText> encode_value_reply(Address address, std::string_view mnemonic,
                                     std::span<const std::string_view> values);

// Time between events (§8, U12): "$0" for no presence, "$XXXX" otherwise, "$0000" overflow.
Result<FrameText> encode_time_between_events(Address address, const TimeBetweenEvents& event);

}  // namespace rangekit::uls
