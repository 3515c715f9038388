// decode_reply (§8, U1, U2, U29, U33).
#include "rangekit/uls/reply.hpp"

#include <string>

#include "rangekit/core/text.hpp"
#include "uls/fields.hpp"

namespace rangekit::uls {
namespace {

Error reply_error(Errc code, const std::string& what) { return make_error(code, "ULS reply: " + what); }

}  // namespace

Result<Reply> decode_reply(const FrameView& frame) {
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
    if (!fields.empty()) return reply_error(Errc::wrong_form, "OK carries " + std::to_string(fields.size()) + " values");
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
    return reply_error(fields.size() < command->reply_fields_min ? Errc::truncated : Errc::overlong,
                       std::string(command->mnemonic) + " reply has " + std::to_string(fields.size()) +
                           " values, expected " + std::to_string(command->reply_fields_min) +
                           (command->reply_fields_max != command->reply_fields_min
                                ? "-" + std::to_string(command->reply_fields_max)
                                : std::string()));
  }
  reply.kind = ReplyKind::value;
  reply.command = command;
  reply.mnemonic = frame.mnemonic;
  for (std::size_t i = 0; i < fields.size(); ++i) reply.value_slots[i] = fields[i];
  reply.value_count = fields.size();
  return reply;
}

Result<Reply> decode_reply(Bytes frame) {
  Result<FrameView> view = parse_frame(frame);
  if (!view) return std::move(view).error();
  return decode_reply(*view);
}

}  // namespace rangekit::uls
