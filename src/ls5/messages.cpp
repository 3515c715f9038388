#include "ls5/messages.hpp"

#include <utility>

#include "rangekit/core/text.hpp"

namespace rangekit::ls5::detail {

std::string quote(std::string_view whole) {
  // A frame is at most 64 bytes; longer text (a whole junk buffer handed to a line
  // parser) is cut, so a message stays a line and costs no more than a frame's worth.
  const std::string_view text = whole.substr(0, max_quoted_bytes);
  std::string out = "'";
  out.reserve(text.size() + 24);
  for (const char c : text) {
    const auto byte = static_cast<std::uint8_t>(c);
    if (byte < 0x20 || byte >= 0x7f) {
      char escaped[5] = {'\\', 'x', 0, 0, 0};
      text::write_hex(byte, 2, escaped + 2);
      out.append(escaped, 4);
    } else {
      out.push_back(c);
    }
  }
  out.push_back('\'');
  if (whole.size() > text.size()) out += "... (" + std::to_string(whole.size()) + " bytes)";
  return out;
}

Error frame_error(Errc code, std::string message) { return make_error(code, "LS5 frame: " + std::move(message)); }

}  // namespace rangekit::ls5::detail
