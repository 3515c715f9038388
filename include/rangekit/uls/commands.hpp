// The ULS command table (ULS §8, "ULS Commands"): one row per mnemonic, shared
// by the codec, emulator, driver, CLI help and docs; plus the pure checks a
// unit applies to a command's values before acting on it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "rangekit/uls/types.hpp"

namespace rangekit::uls {

// One id per row of the table, in §8's order; code switches on it rather than
// comparing mnemonics (the LS5 table does the same).
enum class CommandId : std::uint8_t {
  dither,               // DD
  measure,              // BM
  version,              // ID
  status,               // US
  autostart,            // MA
  start,                // GO
  stop,                 // ST
  pointer_autostart,    // PA
  pointer,              // PT
  save,                 // SU
  current_loop,         // CL
  averaging_weight,     // AW
  baud,                 // BR
  bin_size,             // BS
  bin_threshold,        // BH
  continuous,           // CO
  cooperative_filter,   // FL
  display,              // DM
  fault_current,        // AF
  fault_timeout,        // AT
  long_gate,            // LG
  mode,                 // MM
  output_port,          // MO
  units,                // MU
  power,                // PL
  prf,                  // PF
  ppm,                  // PO
  range_at_20ma,        // AH
  range_at_4ma,         // AL
  termination,          // TE
  short_gate,           // SG
  time_between_events,  // TB
  trip_point,           // TP
  trip_timeout,         // TT
  address,              // UA
  offset,               // OF
};

inline constexpr std::size_t command_count = 36;

enum class Access {
  get_set,   // $CC reads, $CC,values writes
  get_only,  // BM, ID, US
  set_only,  // PT (U16)
  action,    // GO, ST, SU: no values, answered OK/ER
};

enum class ValueKind {
  none,             // actions
  flag,             // 0/1
  enumeration,      // small integer with named values
  unsigned_int,     // decimal integer
  distance,         // decimal, user units (MU), not negative
  signed_distance,  // decimal, user units, may be negative (OF)
  milliamps,        // decimal mA (AF)
  seconds,          // decimal seconds (AT)
  hex_pulses,       // TT: pulse count in hex (U21)
  baud_with_port,   // BR: port, baud
  prf_list,         // PF: 1 or 3 values (U14)
  ppm_list,         // PO: 1 or 2 values (U15)
  address_char,     // UA: one character (U5)
  measurement,      // BM reply: varies with the mode
  text,             // ID reply: free text
  status,           // US reply
};

enum class RequestForm { get, set, action };

// A named value of an enumeration or flag.
struct ValueName {
  std::uint32_t value;
  std::string_view name;
};

struct CommandInfo {
  CommandId id;
  std::string_view mnemonic;  // "MM" (upper case, as encoders write it, U17)
  std::string_view title;     // heading in §8
  std::string_view cli_name;  // "mode"
  Access access;
  ValueKind kind;
  double min;  // every value of a set; distances in metres (U18)
  double max;
  int value_error;                // ULS error number for a value outside min..max (U18)
  int port_error;                 // BR: the port argument's error (84); 0 elsewhere
  bool rejected_while_measuring;  // a set (GO: the action) answers 31 while measuring (U24, U77)
  std::span<const ValueName> value_names;
  std::uint8_t get_fields;      // fields a get carries (BR: the port)
  std::uint8_t set_fields_min;  // fields a set carries
  std::uint8_t set_fields_max;
  std::uint8_t reply_fields_min;  // fields of the get reply (U29)
  std::uint8_t reply_fields_max;
  std::string_view unit;       // what a value counts ("Hz", "pulses", "user units", ...)
  std::string_view reference;  // where the document defines it

  [[nodiscard]] bool has_get() const noexcept { return access == Access::get_set || access == Access::get_only; }
  [[nodiscard]] bool has_set() const noexcept { return access == Access::get_set || access == Access::set_only; }
  // A distance in user units (LG, SG, TP, AH, AL, OF): read and written in MU's units (U18, U76).
  [[nodiscard]] bool is_distance() const noexcept {
    return kind == ValueKind::distance || kind == ValueKind::signed_distance;
  }
  // Name of a value (enumerations and flags), empty when it has none.
  [[nodiscard]] std::string_view value_name(std::uint32_t value) const noexcept;
};

// All 36 rows, in the order §8 presents them.
std::span<const CommandInfo> command_table() noexcept;
// The row of `id`.
const CommandInfo& command_info(CommandId id) noexcept;
// Case-insensitive (U17); null when unknown.
const CommandInfo* find_command(std::string_view mnemonic) noexcept;
// Exact CLI name ("prf", "bin-size"); null when unknown.
const CommandInfo* find_command_by_cli_name(std::string_view cli_name) noexcept;
// A value name as it is typed and printed: "look down" -> "look-down", "off (polled)" -> "off".
std::string value_key(std::string_view name);

std::string_view access_name(Access access) noexcept;
std::string_view value_kind_name(ValueKind kind) noexcept;

// 0 = accepted; otherwise the ULS error number a unit answers with (§10).
struct Verdict {
  int error = 0;
  [[nodiscard]] constexpr bool ok() const noexcept { return error == 0; }
  static constexpr Verdict accept() noexcept { return {}; }
  static constexpr Verdict reject(int number) noexcept { return {number}; }
  friend constexpr bool operator==(Verdict, Verdict) noexcept = default;
};

// What a request with `field_count` values is: a get, a set or an action (U30).
// Error 1 when the command has no such form (a get of PT, a set of ID, ...).
struct FormResult {
  RequestForm form = RequestForm::get;
  Verdict verdict;
};
FormResult request_form(const CommandInfo& command, std::size_t field_count) noexcept;

// Checks a request's fields against the row: its form, the number of values,
// each value's syntax and range. Distances are read in `units` (U18).
// Pure: no device state; cross-field rules are the helpers below.
Verdict validate_request(const CommandInfo& command, std::span<const std::string_view> fields,
                         Units units = Units::metres) noexcept;
// Same, looking the mnemonic up first (unknown mnemonic: error 1).
Verdict validate_request(std::string_view mnemonic, std::span<const std::string_view> fields,
                         Units units = Units::metres) noexcept;

// Cross-field and state rules, each a pure function of the values involved.
// PPM must be greater than AW (error 49, §10, U15).
Verdict check_ppm_against_weight(std::uint64_t pulses_per_measurement, std::uint64_t averaging_weight) noexcept;
// Range at 4 mA and at 20 mA must differ (error 83, U18).
Verdict check_current_loop_range(double range_at_4ma, double range_at_20ma) noexcept;
// Settings that change the measurement (U24) and GO (U77) answer 31 while measuring.
Verdict check_while_measuring(const CommandInfo& command, RequestForm form, bool measuring) noexcept;

}  // namespace rangekit::uls
