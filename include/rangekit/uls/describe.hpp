// Texts for errors about ULS commands: the allowed values of a command (for
// local refusals) and a device error number with §10's explanation.
#pragma once

#include <string>
#include <string_view>

#include "rangekit/core/result.hpp"
#include "rangekit/uls/commands.hpp"

namespace rangekit::uls {

// "10..5000 Hz", "0 off, 1 on", "0..5577.43 feet" (distances in the given units).
std::string allowed_values(const CommandInfo& command, Units units);
// Errc::device_error with device_code = number: "device error 32: Invalid PRF".
Error device_error(int number, std::string_view context);
// The refusal for a request validate_request rejected, naming the allowed values.
Error local_refusal(const CommandInfo& command, std::string_view shown_values, int verdict_error, Units units);
// A decimal without trailing zeros: 3.0 -> "3", 2.25 -> "2.25" (AF, AT).
std::string decimal_text(double value);

}  // namespace rangekit::uls
