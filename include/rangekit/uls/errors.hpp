// ULS §10 error numbers as data.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace rangekit::uls {

// §10 groups the numbers under sub-headings.
enum class ErrorGroup { general, interrupt, table_checksum, rs485, current_loop };

struct ErrorInfo {
  int number = 0;
  std::string_view explanation;   // §10 "Explanation" column
  std::string_view display;       // §10 "ULS Interface Display" column
  bool service_required = false;  // the ☒ mark: must be resolved by LTI (U22)
  ErrorGroup group = ErrorGroup::general;
};

// Every §10 row, by ascending number: 1, then 4 to 87 (2 and 3 do not exist).
std::span<const ErrorInfo> error_table() noexcept;
// Null for numbers the table does not hold.
const ErrorInfo* find_error(int number) noexcept;
std::string_view error_group_name(ErrorGroup group) noexcept;
// A number's §10 text for people: "Lock Not Found (display: Target Not Found)" (the
// explanation, and the Interface Program's display when it says something else);
// "not listed in §10" for a number the table does not hold (U90).
std::string error_text(int number);

// The numbers the codec itself produces or interprets.
namespace error_number {
inline constexpr int invalid_command = 1;     // also every value without its own number (U18)
inline constexpr int target_not_found = 4;    // streamed (U13)
inline constexpr int average_not_filled = 5;  // streamed (U13)
inline constexpr int rx_buffer_overrun = 25;  // a line over the 64-byte frame limit (F5, U78)
inline constexpr int already_measuring = 31;  // settings (U24) and GO (U77) while measuring
inline constexpr int invalid_prf = 32;
inline constexpr int invalid_input_base = 33;  // TT not in hexadecimal (U80)
inline constexpr int invalid_baud = 34;
inline constexpr int invalid_average_weight = 35;
inline constexpr int ppo_not_greater_than_weight = 49;
inline constexpr int invalid_for_mode = 78;  // one-value PO in look down (U79)
inline constexpr int unit_address_not_assigned = 82;
inline constexpr int invalid_current_loop_range = 83;
inline constexpr int invalid_port = 84;
inline constexpr int invalid_measurement_mode = 85;
inline constexpr int not_measuring = 86;
inline constexpr int invalid_min_pulse_width = 87;
}  // namespace error_number

}  // namespace rangekit::uls
