// The LS5 parameters of table 9.2 as the host names them: one readable setting per
// value (a byte, or a value built from several bytes), with its unit. Text in,
// parameter bytes out, and back: the driver, `rangekit ls5 get/set` and the TOML
// configuration all go through this catalog, which is derived from the codec's tables.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/ls5/logical_values.hpp"
#include "rangekit/ls5/parameters.hpp"

namespace rangekit::ls5 {

// How a setting's text maps to bytes.
enum class SettingForm : std::uint8_t {
  byte_number,     // one byte, a plain number ("thinning=4", "median-points=5")
  byte_named,      // one byte with named values ("pre-filter=median", "baud-rate=115200")
  byte_hex,        // one byte shown as two hex digits ("discrete-outputs=12")
  value_number,    // a multi-byte value in its raw unit times scale ("period-ms=1.0", "analog-lower=25000")
  value_mm,        // a result-code value shown in mm of the measurement range (formula 8.1/8.5)
  value_range_mm,  // a fixed range D in codes shown as mm (D × range / 50000)
  value_address,   // IPv4 or MAC text
};

struct HostSetting {
  std::string_view name;  // readable CLI/TOML name
  std::string_view unit;  // "ms", "µs", "mm", "code", "" — for help and docs
  SettingForm form = SettingForm::byte_number;
  std::uint8_t parameter = 0;                                 // single-byte forms
  LogicalValueId value = LogicalValueId::none;                // multi-byte forms
  bool canonical = true;                                      // one canonical setting per parameter byte (config files)
  bool link = false;                                          // changes how the host reaches the sensor (01, 04, 05)
  [[nodiscard]] std::vector<std::uint8_t> addresses() const;  // the parameter bytes, in table order
};

// What a setting needs to know about the sensor besides its bytes.
struct SettingContext {
  SensorModel model{};             // firmware (from ID) and Ethernet
  std::optional<double> range_mm;  // from ID, for the *-mm settings
};

std::span<const HostSetting> host_setting_table() noexcept;
const HostSetting* find_host_setting(std::string_view name) noexcept;
// The canonical setting a parameter byte belongs to.
const HostSetting* host_setting_for_parameter(std::uint8_t address) noexcept;

// Whether the sensor has the setting (firmware version, Ethernet); the error names
// the firmware it needs.
Status check_setting_available(const HostSetting& setting, const SensorModel& model);

// Parses the text and returns the byte writes, every value checked against the
// ranges and the firmware before anything is sent. Errors name the setting and
// the allowed values.
Result<ParameterWrites> encode_setting(const HostSetting& setting, std::string_view text,
                                       const SettingContext& context);
// The check that needs no sensor: `text` against table 9.2 as the newest Ethernet model
// accepts it, before anything is sent (not even ID). A value no LS5 takes is refused with
// encode_setting's error; a value that depends on the sensor (its range for *-mm
// settings, its firmware) passes here and is checked by encode_setting once it is known.
Status check_setting_offline(const HostSetting& setting, std::string_view text);
// Text for the bytes (in the order of addresses()); numbers without units.
Result<std::string> format_setting(const HostSetting& setting, std::span<const std::uint8_t> bytes,
                                   const SettingContext& context);
// Whether format_setting's text is a number (TOML writes it unquoted).
bool setting_is_numeric(const HostSetting& setting) noexcept;
// "1-49, odd", "off | on", "0.1-6553.5 ms" — for refusals and help.
std::string describe_setting_values(const HostSetting& setting, const SettingContext& context);

}  // namespace rangekit::ls5
