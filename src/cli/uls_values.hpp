// Readable names and values for `rangekit uls get/set`: `mode=binning`,
// `prf=2000`, `units=m`, `short-gate=10` (metres), or raw mnemonics `PF=2000`.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/uls/commands.hpp"

namespace rangekit::cli::uls_values {

struct Target {
  const uls::CommandInfo* command = nullptr;
  bool raw = false;  // named by its mnemonic: values go out as typed (user units, hex TT)
};

// "prf", "PF", "pf" -> the row; Errc::unknown_command naming the choices.
Result<Target> find_setting(std::string_view name);

// The wire fields for `value` typed by the user. Readable distances are metres
// ("10", "32.8ft"); readable trip-timeout is seconds; enumerations take a number
// or a name ("binning", "look-down", "m", "ft", "on", "off").
Result<std::vector<std::string>> to_fields(const Target& target, std::string_view value, uls::Units device_units);

// The readable text of a get reply: "binning", "2000,2000,2000 Hz", "10 m".
std::string describe_reply(const uls::CommandInfo& command, const std::vector<std::string>& values,
                           uls::Units device_units);

}  // namespace rangekit::cli::uls_values
