// The one error-to-exit-code table of the rangekit command (docs/cli.md, "Which
// error gives which code"). Before it there were three, and they disagreed.
#include "cli/commands.hpp"

#include <fmt/core.h>

#include <cmath>
#include <cstdlib>

namespace rangekit::cli {

int exit_code_for(const Error& error) {
  switch (error.code) {
    case Errc::device_error:
      return exit_device_error;
    case Errc::timeout:
      return exit_no_reply;
    case Errc::closed:
      return exit_link_lost;
    case Errc::io:
      return exit_io;
    // What the user asked for cannot be done as asked: a value out of range, a name
    // that is no setting, a read-only setting, or a feature this device, firmware or
    // state does not have ("needs a newer firmware", "measure() while streaming").
    case Errc::out_of_range:
    case Errc::wrong_form:
    case Errc::unknown_command:
    case Errc::unknown_parameter:
    case Errc::unsupported:
    case Errc::limit:
      return exit_usage;
    // Bytes, replies, files or values that do not decode.
    case Errc::invalid_frame:
    case Errc::truncated:
    case Errc::overlong:
    case Errc::bad_hex:
    case Errc::bad_number:
    case Errc::bad_checksum:
      return exit_bad_input;
  }
  return exit_bad_input;
}

CLI::Validator in_range(double lowest, double highest, const std::string& unit, bool above_lowest) {
  const std::string range = above_lowest ? fmt::format("more than {:g}, up to {:.0f} {}", lowest, highest, unit)
                                         : fmt::format("{:g} to {:.0f} {}", lowest, highest, unit);
  return CLI::Validator(
      [lowest, highest, range, above_lowest](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value))
          return "'" + text + "' is not a number: give " + range;
        const bool too_low = above_lowest ? value <= lowest : value < lowest;
        if (too_low || value > highest) return text + " is out of range: give " + range;
        return {};
      },
      range);
}

}  // namespace rangekit::cli
