// Replies to requests (§8 "Message Format"): $OK, $ER,n, or $CC,values.
#pragma once

#include <span>
#include <string_view>

#include "rangekit/core/result.hpp"
#include "rangekit/uls/commands.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/frame.hpp"

namespace rangekit::uls {

enum class ReplyKind { ok, error, value };

struct Reply {
  ReplyKind kind = ReplyKind::ok;
  Address source;
  int error_number = 0;                  // kind == error
  const ErrorInfo* error = nullptr;      // kind == error; null for numbers §10 does not list (U31)
  const CommandInfo* command = nullptr;  // kind == value
  std::string_view mnemonic;             // kind == value, as received
  std::array<std::string_view, max_fields> value_slots{};
  std::size_t value_count = 0;

  [[nodiscard]] std::span<const std::string_view> values() const noexcept { return {value_slots.data(), value_count}; }
};

// Reads a reply. Value replies must name a known command with a get, carry the
// number of values its get reply has and values of the row's kind and range
// (U29; distances read in `units`; UA's value is decimal, U5). BM replies are
// only counted here: read them with decode_measurement. No allocation on success.
Result<Reply> decode_reply(const FrameView& frame, Units units = Units::metres);
Result<Reply> decode_reply(Bytes frame, Units units = Units::metres);

}  // namespace rangekit::uls
