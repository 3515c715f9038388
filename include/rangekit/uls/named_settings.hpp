// Readable names and values of ULS settings, one copy for `rangekit uls get/set` and the
// service: `prf-hz=2000`, `short-gate-m=10`, or raw `PF=2000`. A name ends in its unit and
// the value is bare, as the LS5's `period-ms` (U96, docs/cli.md).
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/uls/commands.hpp"
#include "rangekit/uls/driver.hpp"

namespace rangekit::uls::named {

struct Target {
  const CommandInfo* command = nullptr;
  bool raw = false;  // named by its mnemonic: values go out as typed (user units, hex TT)
  std::string port;  // BR by port name: "0" (baud-configuration) or "1" (baud-output)
};

// The name `get` prints and `set` takes: "long-gate-m", "prf-hz", "mode".
std::string setting_key(const CommandInfo& command);

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
Result<std::vector<std::string>> to_fields(const Target& target, std::string_view value, Units device_units);

// The readable value of a get reply, its unit in the name: "binning", "2000,2000,2000", "10".
Reading describe_reply(const CommandInfo& command, const std::vector<std::string>& values, Units device_units);

// uls::readable()'s text ("10 m", "1080000 pulses") in the get style ("10", "360").
std::string without_unit(const CommandInfo& command, const std::string& readable_text);

// --- On a unit (through the driver) -----------------------------------------

// One line of `get`: the name, the value, and the wire reply as a comment ("PF=2000,2000,2000").
struct Value {
  std::string key;
  Reading reading;
  std::string comment;
};
// The lines of one setting (BR: one per port, or only `target.port`'s); UA's error 82 is the
// line `address=unassigned`.
Result<std::vector<Value>> read_setting(Driver& driver, const Target& target, Units device_units);
// Every readable setting, in table order, as `rangekit uls get` lists them.
std::vector<Target> readable_targets();
Result<std::vector<Value>> read_all(Driver& driver);

struct Assignment {
  Target target;
  std::string value;
};
// NAME=VALUE pairs checked before anything is sent (distances in metres), ordered so that
// BR (the port switches after its $OK, U36) and UA (the unit answers elsewhere) go last.
Result<std::vector<Assignment>> plan(const std::vector<std::pair<std::string, std::string>>& pairs);
// The name a set echoes: as get prints it, or the mnemonic it was given by.
std::string assignment_name(const Target& target);
struct Written {
  const Assignment* assignment = nullptr;
  std::vector<std::string> fields;  // as sent, distances in the unit's MU
};
// Sends each assignment in order, reading MU first when a distance needs it; stops at the
// first refusal. `written` is told of each one the unit accepted.
Status apply(Driver& driver, const std::vector<Assignment>& assignments,
             const std::function<void(const Written&)>& written = {});
// `set` from any state, for the CLI and the service alike: a unit that measures refuses
// settings (error 31, U24), so it is stopped first and started again after; each value is
// sent (apply), read back and compared, so a value the unit took otherwise is an error. True
// when the unit was measuring. After a UA it is started at its new address.
Result<bool> write(Driver& driver, const std::vector<Assignment>& assignments,
                   const std::function<void(const Written&)>& written = {});

}  // namespace rangekit::uls::named
