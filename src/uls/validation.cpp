// The checks a unit applies to a request before acting on it (U16, U18, U24,
// U30, U76, U77, U80). Pure functions of the command row and the request's fields.

#include "rangekit/core/text.hpp"
#include "rangekit/uls/commands.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/formulas.hpp"
#include "uls/fields.hpp"

namespace rangekit::uls {
namespace {

constexpr Verdict invalid_command = Verdict::reject(error_number::invalid_command);

// Integer values: a field that is not a number is error 1 (U18), a number
// outside the row's range is the row's own error.
Verdict check_integer(std::string_view field, double min, double max, int range_error) noexcept {
  const detail::IntegerField value = detail::read_integer(field);
  if (!value.is_number) return invalid_command;
  if (!value.within(static_cast<std::int64_t>(min), static_cast<std::int64_t>(max))) {
    return Verdict::reject(range_error);
  }
  return Verdict::accept();
}

// Decimal values (distances, mA, seconds), read in user units for distances.
Verdict check_decimal(std::string_view field, const CommandInfo& row, Units units) noexcept {
  const std::optional<double> value = text::parse_decimal(field, '.');
  if (!value) return invalid_command;
  // Distance limits as the unit writes them in its units (U76): what a get reports is accepted back.
  const bool within =
      row.is_distance() ? distance_within(*value, units, row.min, row.max) : *value >= row.min && *value <= row.max;
  if (!within) return Verdict::reject(row.value_error);
  return Verdict::accept();
}

// TT, the one value §8 gives in hexadecimal: a digit outside 0-9/A-F is error 33
// "Invalid Input Base" (U80); more than 8 digits is the row's own error.
Verdict check_hex(std::string_view field, const CommandInfo& row) noexcept {
  for (const char c : field) {
    if (!text::is_hex_digit(c)) return Verdict::reject(error_number::invalid_input_base);
  }
  return parse_trip_timeout(field) ? Verdict::accept() : Verdict::reject(row.value_error);
}

Verdict check_port(std::string_view field, const CommandInfo& row) noexcept {
  return check_integer(field, 0, 1, row.port_error);
}

Verdict check_baud(std::string_view field, const CommandInfo& row) noexcept {
  const detail::IntegerField value = detail::read_integer(field);
  if (!value.is_number) return invalid_command;
  if (value.negative || value.magnitude > UINT32_MAX || !is_baud_choice(static_cast<std::uint32_t>(value.magnitude))) {
    return Verdict::reject(row.value_error);
  }
  return Verdict::accept();
}

Verdict check_address_char(std::string_view field, const CommandInfo& row) noexcept {
  if (field.size() != 1) return invalid_command;
  const auto byte = static_cast<std::uint8_t>(field.front());
  if (byte < row.min || byte > row.max) return Verdict::reject(row.value_error);
  return Verdict::accept();
}

Verdict check_each(std::span<const std::string_view> fields, const CommandInfo& row) noexcept {
  for (const std::string_view field : fields) {
    const Verdict verdict = check_integer(field, row.min, row.max, row.value_error);
    if (!verdict.ok()) return verdict;
  }
  return Verdict::accept();
}

Verdict check_set_values(const CommandInfo& row, std::span<const std::string_view> fields, Units units) noexcept {
  switch (row.kind) {
    case ValueKind::flag:
    case ValueKind::enumeration:
    case ValueKind::unsigned_int:
      return check_integer(fields[0], row.min, row.max, row.value_error);
    case ValueKind::prf_list:
      if (fields.size() == 2) return invalid_command;  // one value or all three (U14)
      return check_each(fields, row);
    case ValueKind::ppm_list:
      return check_each(fields, row);
    case ValueKind::distance:
    case ValueKind::signed_distance:
    case ValueKind::milliamps:
    case ValueKind::seconds:
      return check_decimal(fields[0], row, units);
    case ValueKind::hex_pulses:
      return check_hex(fields[0], row);
    case ValueKind::baud_with_port: {
      const Verdict port = check_port(fields[0], row);
      if (!port.ok()) return port;
      return check_baud(fields[1], row);
    }
    case ValueKind::address_char:
      return check_address_char(fields[0], row);
    case ValueKind::none:
    case ValueKind::measurement:
    case ValueKind::text:
    case ValueKind::status:
      return invalid_command;  // no set form; request_form already refused it
  }
  return invalid_command;
}

}  // namespace

FormResult request_form(const CommandInfo& command, std::size_t field_count) noexcept {
  const bool get_shape = field_count == command.get_fields;
  const bool set_shape =
      field_count >= command.set_fields_min && field_count <= command.set_fields_max && command.set_fields_max > 0;
  switch (command.access) {
    case Access::action:
      if (field_count == 0) return {RequestForm::action, Verdict::accept()};
      break;
    case Access::get_only:
      if (get_shape) return {RequestForm::get, Verdict::accept()};
      break;
    case Access::set_only:
      if (set_shape) return {RequestForm::set, Verdict::accept()};
      break;
    case Access::get_set:
      if (get_shape) return {RequestForm::get, Verdict::accept()};
      if (set_shape) return {RequestForm::set, Verdict::accept()};
      break;
  }
  return {RequestForm::get, invalid_command};
}

Verdict validate_request(const CommandInfo& command, std::span<const std::string_view> fields, Units units) noexcept {
  const FormResult shape = request_form(command, fields.size());
  if (!shape.verdict.ok()) return shape.verdict;
  switch (shape.form) {
    case RequestForm::action:
      return Verdict::accept();
    case RequestForm::get:
      // BR's get names the port it asks about (§8 Set/Get Baud Rate).
      if (command.kind == ValueKind::baud_with_port) return check_port(fields[0], command);
      return Verdict::accept();
    case RequestForm::set:
      return check_set_values(command, fields, units);
  }
  return invalid_command;
}

Verdict validate_request(std::string_view mnemonic, std::span<const std::string_view> fields, Units units) noexcept {
  const CommandInfo* command = find_command(mnemonic);
  if (command == nullptr) return invalid_command;
  return validate_request(*command, fields, units);
}

Verdict check_ppm_against_weight(std::uint64_t pulses_per_measurement, std::uint64_t averaging_weight) noexcept {
  if (pulses_per_measurement <= averaging_weight) {
    return Verdict::reject(error_number::ppo_not_greater_than_weight);
  }
  return Verdict::accept();
}

Verdict check_current_loop_range(double range_at_4ma, double range_at_20ma) noexcept {
  if (range_at_4ma == range_at_20ma) return Verdict::reject(error_number::invalid_current_loop_range);
  return Verdict::accept();
}

Verdict check_while_measuring(const CommandInfo& command, RequestForm form, bool measuring) noexcept {
  // Sets that change the measurement (U24) and GO, "Instrument Is Already Measuring" (U77).
  if (measuring && form != RequestForm::get && command.rejected_while_measuring) {
    return Verdict::reject(error_number::already_measuring);
  }
  return Verdict::accept();
}

}  // namespace rangekit::uls
