// scan_frame: the shared line framer with ULS rules (F1-F5, U4, U25).
#include <algorithm>

#include "rangekit/core/text.hpp"
#include "rangekit/uls/frame.hpp"

namespace rangekit::uls {
namespace {

// '$' frames have no address slot; '#' frames have one at offset 1.
constexpr LineFramerRules plain_rules{"$#", '\r', max_frame_length, false, 0};
constexpr LineFramerRules addressed_rules{"$#", '\r', max_frame_length, true, 1};

bool letter_is(std::uint8_t byte, char upper) noexcept { return text::to_upper(static_cast<char>(byte)) == upper; }

// U25: a UA set may carry an address character 0x7F-0xEF (U5), which F4 would
// refuse inside a frame. "$UA,<b><CR>" or "#aUA,<b><CR>" is let through here
// only in that exact shape; anything else gets the ordinary rules.
bool starts_unit_address_set(Bytes buffer, std::size_t value_at) noexcept {
  const std::size_t mnemonic_at = value_at - 3;
  if (buffer.size() <= value_at) return false;
  if (mnemonic_at == 2 && buffer[1] == '\r') return false;  // "#<CR>": no address byte
  return letter_is(buffer[mnemonic_at], 'U') && letter_is(buffer[mnemonic_at + 1], 'A') &&
         buffer[mnemonic_at + 2] == ',' && buffer[value_at] >= 0x7F;
}

}  // namespace

FrameScan scan_frame(Bytes buffer) noexcept {
  // The common frame: a start byte, then only bytes above '$' and below DEL up to
  // the CR. scan_line_frame gives the same answer for it (such a frame cannot be
  // the U25 UA shape, whose value byte is 0x7F or above), more slowly.
  if (!buffer.empty() && (buffer[0] == '$' || buffer[0] == '#')) {
    const std::size_t window = std::min(buffer.size(), max_frame_length + 1);
    std::size_t end = 1;
    while (end < window && buffer[end] > '$' && buffer[end] < 0x7F) ++end;
    if (end < window && buffer[end] == '\r') return FrameScan::complete(buffer.first(end), end + 1);
  }
  const bool addressed = !buffer.empty() && buffer[0] == '#';
  const std::size_t value_at = addressed ? 5 : 4;
  if (!buffer.empty() && (buffer[0] == '$' || addressed) && starts_unit_address_set(buffer, value_at)) {
    if (buffer.size() == value_at + 1) return FrameScan::need_more();
    if (buffer[value_at + 1] == '\r') return FrameScan::complete(buffer.first(value_at + 1), value_at + 2);
  }
  return scan_line_frame(buffer, addressed ? addressed_rules : plain_rules);
}

}  // namespace rangekit::uls
