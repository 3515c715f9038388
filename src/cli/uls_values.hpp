// Readable names and values for `rangekit uls get/set`: `mode=binning`,
// `prf-hz=2000`, `units=m`, `short-gate-m=10`, or raw mnemonics `PF=2000`. A name
// carries its unit (`-m`, `-ma`, `-s`, `-hz`), the value is a bare number: the LS5's
// style (`period-ms`), one for both families (issue 11 point 5, docs/cli.md).
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
  std::string port;  // BR by port name: "0" (baud-configuration) or "1" (baud-output)
};

// The name `get` prints and `set` takes: "long-gate-m", "prf-hz", "mode".
std::string setting_key(const uls::CommandInfo& command);

enum class Purpose { get, set };
// "prf-hz", "prf" (the earlier spelling), "PF", "pf" -> the row; Errc::unknown_command
// naming the names there are (for set only the writable ones); for set, a read-only
// name is Errc::wrong_form saying so.
Result<Target> find_setting(std::string_view name, Purpose purpose = Purpose::get);

// The names `set` accepts, comma separated (for --help and errors).
std::string writable_names();

// A value for `info`/`get`: the text, and whether it is a number (or a list of
// numbers) that --json prints as such.
struct Reading {
  std::string text;
  bool number = false;
};

// The wire fields for `value` typed by the user. Readable distances are metres
// ("10", "32.8ft"); readable trip-timeout is seconds; enumerations take a number
// or a name ("binning", "look-down", "m", "ft", "on", "off").
Result<std::vector<std::string>> to_fields(const Target& target, std::string_view value, uls::Units device_units);

// The readable value of a get reply, its unit in the name: "binning", "2000,2000,2000", "10".
Reading describe_reply(const uls::CommandInfo& command, const std::vector<std::string>& values,
                       uls::Units device_units);

// uls::readable()'s text ("10 m", "1080000 pulses") in the get style ("10", "360").
std::string without_unit(const uls::CommandInfo& command, const std::string& readable_text);

}  // namespace rangekit::cli::uls_values
