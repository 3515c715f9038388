// All LS5 settings as a readable TOML file (the configuration program's parameter
// file): save what the sensor holds, load a file (upload, read back, verify every
// value) and diff a file against the sensor. Values are readable names and units
// (host_settings.hpp); link settings (address, baud, byte format) are saved and
// compared but never uploaded, so a load cannot cut the host off the sensor.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/ls5/driver.hpp"
#include "rangekit/ls5/host_settings.hpp"

namespace rangekit::ls5 {

struct ConfigEntry {
  const HostSetting* setting = nullptr;
  std::string value;                // readable text (format_setting)
  std::vector<std::uint8_t> bytes;  // as read from the sensor; empty for a file entry
};

struct DeviceConfig {
  std::uint8_t address = 0x01;                   // where it was read from
  std::optional<Identification> identification;  // for the file's header comment
  std::vector<ConfigEntry> entries;              // canonical settings, table order
};

// Reads every canonical setting the sensor has (firmware, Ethernet).
Result<DeviceConfig> read_device_config(Driver& driver);

std::string config_to_toml(const DeviceConfig& config);
// Errors name the source, the line and the key.
Result<DeviceConfig> parse_config_toml(std::string_view text, const std::string& source_name);

Status save_config_file(const DeviceConfig& config, const std::string& path);  // atomic: temp file + rename
Result<DeviceConfig> load_config_file(const std::string& path);

struct ConfigDifference {
  const HostSetting* setting = nullptr;
  std::string file_value;
  std::string device_value;
};

struct ConfigLoadReport {
  std::vector<std::string> written;          // settings uploaded
  std::vector<std::string> skipped;          // link settings, and settings this sensor lacks (with why)
  std::vector<ConfigDifference> mismatches;  // read back differently after the upload
};

// Compares a file with the sensor's values (by bytes, so 10 and 10.0 are equal).
Result<std::vector<ConfigDifference>> diff_config(Driver& driver, const DeviceConfig& file);
// Checks every value first (nothing is sent if one is refused), writes, reads back, verifies.
Result<ConfigLoadReport> upload_config(Driver& driver, const DeviceConfig& file);

}  // namespace rangekit::ls5
