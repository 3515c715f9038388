#include "cli/describe.hpp"

#include <fmt/core.h>

namespace rangekit::cli {

std::string printable(Bytes frame) {
  std::string text;
  for (const auto byte : frame) {
    if (byte >= 0x20 && byte < 0x7f)
      text.push_back(static_cast<char>(byte));
    else
      text += fmt::format("<{:02X}>", byte);
  }
  return text;
}

}  // namespace rangekit::cli
