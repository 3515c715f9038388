// The identification reply's 35-character field (§9.2, conformance L2):
//   version (10, left-justified) 'b' lower boundary (6) 'd' range (7) "s/n" serial (7 digits)
//   "LS5.6.0   b8,1234d40,0010s/n0000157"
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "rangekit/core/result.hpp"
#include "rangekit/ls5/fixed_text.hpp"
#include "rangekit/ls5/version.hpp"

namespace rangekit::ls5 {

inline constexpr std::size_t identification_field_length = 35;
inline constexpr std::size_t identification_version_width = 10;
inline constexpr std::size_t identification_lower_width = 6;
inline constexpr std::size_t identification_range_width = 7;
inline constexpr std::size_t identification_serial_width = 7;

struct Identification {
  FixedText<identification_version_width> version_text;  // trailing spaces removed
  std::optional<FirmwareVersion> version;                // when version_text parses (conformance L17)
  double lower_boundary_mm = 0.0;
  double range_mm = 0.0;
  std::uint32_t serial_number = 0;  // 0-9999999
};

using IdentificationField = FixedText<identification_field_length>;

// Reads the fields by position; the separator letters are not checked (L2).
Result<Identification> decode_identification_field(std::string_view field);
// Writes the field with the letters b, d, s/n and as many decimals as fit.
Result<IdentificationField> encode_identification_field(const Identification& identification);

// An Identification whose version_text and version agree.
Result<Identification> make_identification(std::string_view version_text, double lower_boundary_mm, double range_mm,
                                           std::uint32_t serial_number);

}  // namespace rangekit::ls5
