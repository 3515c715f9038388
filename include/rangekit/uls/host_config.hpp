// A unit's settings as a readable TOML file: the Interface Program's `.uls`
// configuration file (§2 File Menu), with `save`, `load` (upload, then read
// back and verify every value) and `diff` against the device.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/uls/commands.hpp"
#include "rangekit/uls/driver.hpp"

namespace rangekit::uls {

// One setting: the command and its values as numbers. Distances are metres,
// enumerations and flags their wire numbers, TT its pulse count.
struct Setting {
  const CommandInfo* command = nullptr;
  std::vector<double> values;
};

struct DeviceConfig {
  std::vector<Setting> settings;  // in the order config_commands() lists them
  std::string version;            // ID when read from a unit
};

// The settings a config file holds: every get+set row of §8 except the link
// settings BR and UA, which would cut the connection (U64). MU comes first.
std::vector<const CommandInfo*> config_commands();

// The wire values of a setting in the given units ("2000", "32.81", "107AC0").
std::vector<std::string> to_wire(const Setting& setting, Units units);
// A setting from its wire values; Errc::invalid_frame when they do not read.
Result<Setting> from_wire(const CommandInfo& command, const std::vector<std::string>& values, Units units);
// A readable value ("binning", "on", "2000,2000,2000", "10 m") for listings.
std::string readable(const Setting& setting);

// Reads every setting of config_commands() from the unit.
Result<DeviceConfig> read_config(Driver& driver);
// The TOML text; `origin` goes into the header comment.
std::string config_to_toml(const DeviceConfig& config, std::string_view origin);
// Reads TOML text; errors name the file, the line and the key. Keys not
// present keep no value (load leaves them as they are on the unit).
Result<DeviceConfig> config_from_toml(std::string_view text, std::string_view file_name);

struct ConfigDifference {
  const CommandInfo* command = nullptr;
  std::string wanted;  // file (readable)
  std::string actual;  // device (readable)
};
// Settings whose wire values differ (compared in the device's units).
std::vector<ConfigDifference> diff_config(const DeviceConfig& wanted, const DeviceConfig& actual);

struct LoadReport {
  std::size_t sent = 0;
  std::vector<ConfigDifference> mismatches;  // after reading back
};
// Stops the unit if it measures (settings answer 31 then, U24), uploads MU
// first, retries sets refused for an order (49 PPM vs AW, 83 AL vs AH) once at
// the end, reads everything back and reports what differs; restarts measuring
// if it was measuring. Errc::device_error if a set is refused for good.
Result<LoadReport> load_config(Driver& driver, const DeviceConfig& config);

// The factory settings (§2 screenshots, U35), for `rangekit uls reset` (U65).
DeviceConfig factory_config();

}  // namespace rangekit::uls
