// Firmware versions as the LS5 reports them at identification ("LS5.6.0") and as
// the document names them ("LS5.12.x"). Features are gated on these (conformance L6).
#pragma once

#include <compare>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "rangekit/core/result.hpp"

namespace rangekit::ls5 {

struct FirmwareVersion {
  std::uint16_t major = 0;  // the 6 of LS5.6.0
  std::uint16_t minor = 0;  // the 0 of LS5.6.0; 0 when written as 'x'
  bool any_minor = false;   // written "LS5.12.x": every LS5.12 release

  // Orders by (major, minor); "LS5.12.x" compares as LS5.12.0, the first release it covers.
  friend constexpr std::strong_ordering operator<=>(const FirmwareVersion& a, const FirmwareVersion& b) noexcept {
    if (a.major != b.major) return a.major <=> b.major;
    return a.minor <=> b.minor;
  }
  friend constexpr bool operator==(const FirmwareVersion& a, const FirmwareVersion& b) noexcept {
    return a.major == b.major && a.minor == b.minor;
  }

  [[nodiscard]] constexpr bool at_least(const FirmwareVersion& required) const noexcept { return *this >= required; }

  // "LS5.6.0" / "LS5.12.x"; for messages and tables.
  [[nodiscard]] std::string to_string() const;
};

// Versions the document names (table 9.2 notes 2-5, §8.5, §8.8, §8.14).
inline constexpr FirmwareVersion any_firmware{0, 0};
inline constexpr FirmwareVersion firmware_6_0{6, 0};          // baud rates above 115200, standby mode (§8.2)
inline constexpr FirmwareVersion firmware_7_0{7, 0};          // exposure time and priority (§8.5)
inline constexpr FirmwareVersion firmware_8_0{8, 0};          // type of preliminary result (§8.8)
inline constexpr FirmwareVersion firmware_9_0{9, 0};          // latching with recalculation (§8.14)
inline constexpr FirmwareVersion firmware_12_x{12, 0, true};  // Ethernet settings (table 9.2 note 5)

// Parses "LS5.<major>.<minor>" where major and minor are 1-3 decimal digits and
// minor may be 'x' (any). Nothing else is accepted: no spaces, no suffix.
Result<FirmwareVersion> parse_firmware_version(std::string_view text);
// The same without an error message: no allocation, for decoders.
std::optional<FirmwareVersion> try_parse_firmware_version(std::string_view text) noexcept;

}  // namespace rangekit::ls5
