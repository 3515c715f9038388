// decode_reply (§8, U1, U2, U29, U31).
#include "rangekit/uls/reply.hpp"

#include <string>

#include "rangekit/core/text.hpp"
#include "rangekit/uls/formulas.hpp"
#include "uls/fields.hpp"

namespace rangekit::uls {
namespace {

Error reply_error(Errc code, const std::string& what) { return make_error(code, "ULS reply: " + what); }

Error value_error(const CommandInfo& command, std::string_view value, const char* problem) {
  return reply_error(Errc::out_of_range,
                     std::string(command.mnemonic) + " value " + detail::quoted(value) + " " + problem);
}

Status check_integer(const CommandInfo& command, std::string_view value, double min, double max) {
  const detail::IntegerField number = detail::read_integer(value);
  if (!number.is_number)
    return reply_error(Errc::bad_number,
                       std::string(command.mnemonic) + " value " + detail::quoted(value) + " is not an integer");
  if (!number.within(static_cast<std::int64_t>(min), static_cast<std::int64_t>(max))) {
    return value_error(command, value, "is out of range");
  }
  return ok_status();
}

Status check_decimal(const CommandInfo& command, std::string_view value, Units units) {
  const std::optional<double> number = text::parse_decimal(value, '.');
  if (!number)
    return reply_error(Errc::bad_number,
                       std::string(command.mnemonic) + " value " + detail::quoted(value) + " is not a number");
  const bool distance = command.is_distance();
  const bool within = distance ? distance_within(*number, units, command.min, command.max)
                               : *number >= command.min && *number <= command.max;
  if (!within) return value_error(command, value, "is out of range");  // distances: U76
  return ok_status();
}

// The values of a get reply, by the row's kind (U29).
Status check_values(const CommandInfo& command, std::span<const std::string_view> values, Units units) {
  switch (command.kind) {
    case ValueKind::flag:
    case ValueKind::enumeration:
    case ValueKind::unsigned_int:
    case ValueKind::prf_list:
    case ValueKind::ppm_list:
      for (const std::string_view value : values) {
        Status checked = check_integer(command, value, command.min, command.max);
        if (!checked) return checked;
      }
      return ok_status();
    case ValueKind::distance:
    case ValueKind::signed_distance:
    case ValueKind::milliamps:
    case ValueKind::seconds:
      return check_decimal(command, values[0], units);
    case ValueKind::hex_pulses:
      if (!parse_trip_timeout(values[0])) {
        return reply_error(Errc::bad_hex, "TT value " + detail::quoted(values[0]) + " is not 1-8 hex digits");
      }
      return ok_status();
    case ValueKind::baud_with_port: {
      Status port = check_integer(command, values[0], 0, 1);
      if (!port) return port;
      const std::optional<std::uint64_t> baud = text::parse_unsigned(values[1], 6);
      if (!baud || !is_baud_choice(static_cast<std::uint32_t>(*baud))) {
        return value_error(command, values[1], "is not a baud rate the ULS offers");
      }
      return ok_status();
    }
    case ValueKind::address_char:  // the get reply is the decimal value (U5)
      return check_integer(command, values[0], command.min, command.max);
    case ValueKind::status:
      if (!to_unit_status(text::parse_unsigned(values[0], 2).value_or(99))) {
        return value_error(command, values[0], "is not a unit status (0, 1, 3, 7, 11)");
      }
      return ok_status();
    case ValueKind::measurement:  // depends on the mode: decode_measurement reads it
    case ValueKind::text:
    case ValueKind::none:
      return ok_status();
  }
  return ok_status();
}

}  // namespace

Result<Reply> decode_reply(const FrameView& frame, Units units) {
  if (frame.kind == FrameKind::time_between_events) {
    return reply_error(Errc::wrong_form, "time-between-events frame is not a reply");
  }
  if (frame.address.is_broadcast()) {
    return reply_error(Errc::wrong_form, "reply from broadcast address " + detail::hex_byte(frame.address.byte) +
                                             " (units never answer a broadcast, U4)");
  }
  Reply reply;
  reply.source = frame.address;
  const std::span<const std::string_view> fields = frame.fields();

  if (frame.is("OK")) {
    if (!fields.empty())
      return reply_error(Errc::wrong_form, "OK carries " + std::to_string(fields.size()) + " values");
    reply.kind = ReplyKind::ok;
    return reply;
  }
  if (frame.is("ER")) {
    if (fields.size() != 1) {
      return reply_error(fields.empty() ? Errc::truncated : Errc::overlong,
                         "ER needs one error number, got " + std::to_string(fields.size()) + " fields");
    }
    const std::optional<std::uint64_t> number = text::parse_unsigned(fields[0], 3);
    if (!number) {
      return reply_error(Errc::bad_number, "error number " + detail::quoted(fields[0]) + " is not 1-3 digits");
    }
    if (*number == 0) return reply_error(Errc::out_of_range, "error number 0 is not an error (U31)");
    reply.kind = ReplyKind::error;
    reply.error_number = static_cast<int>(*number);
    reply.error = find_error(reply.error_number);
    return reply;
  }

  const CommandInfo* command = find_command(frame.mnemonic);
  if (command == nullptr) {
    return reply_error(Errc::unknown_command, "mnemonic " + detail::quoted(frame.mnemonic) + " is not a ULS command");
  }
  if (!command->has_get()) {
    return reply_error(Errc::wrong_form, std::string(command->mnemonic) + " has no get, so no value reply");
  }
  if (fields.size() < command->reply_fields_min || fields.size() > command->reply_fields_max) {
    return reply_error(
        fields.size() < command->reply_fields_min ? Errc::truncated : Errc::overlong,
        std::string(command->mnemonic) + " reply has " + std::to_string(fields.size()) + " values, expected " +
            std::to_string(command->reply_fields_min) +
            (command->reply_fields_max != command->reply_fields_min ? "-" + std::to_string(command->reply_fields_max)
                                                                    : std::string()));
  }
  Status checked = check_values(*command, fields, units);
  if (!checked) return std::move(checked).error();
  reply.kind = ReplyKind::value;
  reply.command = command;
  reply.mnemonic = frame.mnemonic;
  for (std::size_t i = 0; i < fields.size(); ++i) reply.value_slots[i] = fields[i];
  reply.value_count = fields.size();
  return reply;
}

Result<Reply> decode_reply(Bytes frame, Units units) {
  Result<FrameView> view = parse_frame(frame);
  if (!view) return std::move(view).error();
  return decode_reply(*view, units);
}

}  // namespace rangekit::uls
