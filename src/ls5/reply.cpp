#include "rangekit/ls5/reply.hpp"

#include <string>

#include "ls5/frame_fields.hpp"
#include "ls5/messages.hpp"
#include "rangekit/core/text.hpp"

namespace rangekit::ls5 {
namespace {

using detail::frame_error;
using detail::quote;

constexpr std::size_t result_digits = 5;
constexpr std::size_t identification_frame_length = 3 + identification_field_length;  // '%' AA field

bool valid_code(std::uint16_t code) noexcept {
  return code <= max_result_code || code == code_no_measurement_yet || code == code_no_signal;
}

// A sensor has an address 01-FF; nothing answers from the broadcast address (L15).
Status check_reply_address(std::uint8_t address) {
  if (address == broadcast_address) {
    return frame_error(Errc::wrong_form, "a reply never comes from address 00: broadcasts are not answered");
  }
  return ok_status();
}

Result<ResultCode> parse_result_digits(std::string_view digits, std::string_view frame) {
  bool all_digits = digits.size() == result_digits;
  for (const char c : digits) all_digits = all_digits && text::is_digit(c);
  if (!all_digits)
    return frame_error(Errc::bad_number,
                       "result " + quote(digits) + " in " + quote(frame) + " is not 5 decimal digits");
  const auto value = text::parse_unsigned(digits, result_digits);
  auto code = make_result_code(static_cast<std::uint32_t>(*value));
  if (!code) return frame_error(code.error().code, code.error().message + " in " + quote(frame));
  return *code;
}

bool digits_only(std::string_view text) noexcept {
  if (text.empty()) return false;
  for (const char c : text) {
    if (!text::is_digit(c)) return false;
  }
  return true;
}

Result<Reply> parse_stream_record(std::string_view frame) {
  const std::string_view digits = frame.substr(1);
  if (digits.size() != result_digits) {
    return frame_error(digits.size() < result_digits ? Errc::truncated : Errc::overlong,
                       "stream record " + quote(frame) + " must have 5 digits (L1)");
  }
  auto code = parse_result_digits(digits, frame);
  if (!code) return std::move(code).error();
  return Reply::stream_record(*code);
}

Result<Reply> parse_identification_reply(std::string_view frame) {
  if (frame.size() != identification_frame_length) {
    return frame_error(frame.size() < identification_frame_length ? Errc::truncated : Errc::overlong,
                       "identification reply " + quote(frame) + " has " + std::to_string(frame.size()) +
                           " characters, expected '%', the address and 35 characters (L2)");
  }
  auto address = detail::parse_address(frame);
  if (!address) return std::move(address).error();
  if (Status from = check_reply_address(*address); !from) return std::move(from).error();
  auto id = decode_identification_field(frame.substr(3));
  if (!id) return frame_error(id.error().code, id.error().message);
  return Reply::identification_of(*address, *id);
}

Result<Reply> parse_addressed_reply(std::string_view frame) {
  auto address = detail::parse_address(frame);
  if (!address) return std::move(address).error();
  if (Status from = check_reply_address(*address); !from) return std::move(from).error();
  auto command = detail::parse_command(frame);
  if (!command) return std::move(command).error();
  const CommandInfo& info = **command;
  if (info.response == ResponseForm::identification) {
    return frame_error(Errc::wrong_form, "the identification reply starts with '%', got " + quote(frame));
  }
  if (info.response == ResponseForm::stream) {
    return frame_error(Errc::wrong_form,
                       "ST has no reply of its own: stream records are '!ddddd', got " + quote(frame));
  }
  const char* what = info.response == ResponseForm::result ? "a 5-digit result"
                     : reply_argument_length(info) == 4    ? "a parameter address and value (aadd)"
                                                           : "no argument";
  Status length = detail::check_argument_length(frame, info, reply_argument_length(info), what);
  if (!length) return std::move(length).error();

  const std::size_t at = 3 + info.code.size();
  Reply reply;
  reply.address = *address;
  reply.command = info.id;
  switch (info.response) {
    case ResponseForm::result: {
      auto code = parse_result_digits(frame.substr(at), frame);
      if (!code) return std::move(code).error();
      reply.kind = ReplyKind::result;
      reply.result = *code;
      return reply;
    }
    case ResponseForm::parameter_value:
    case ResponseForm::echo: {
      reply.kind = info.response == ResponseForm::echo ? ReplyKind::echo : ReplyKind::parameter_value;
      if (reply_argument_length(info) == 4) {
        auto parameter = detail::parse_hex_byte(frame, at, "parameter address");
        if (!parameter) return std::move(parameter).error();
        auto value = detail::parse_hex_byte(frame, at + 2, "parameter value");
        if (!value) return std::move(value).error();
        reply.parameter = *parameter;
        reply.value = *value;
      }
      return reply;
    }
    case ResponseForm::identification:
    case ResponseForm::stream:
      break;
  }
  return frame_error(Errc::wrong_form, "unexpected reply form in " + quote(frame));
}

const Reply blank_reply{};

// Any reply, with a message that names what is wrong with a bad one.
// Kept out of line: inlined, its stack frame made every stream record pay for it.
[[gnu::noinline]] Result<Reply> parse_any_reply(Bytes frame_bytes) {
  const std::string_view frame = as_text(frame_bytes);
  if (frame.empty()) return frame_error(Errc::truncated, "empty reply");
  if (frame.front() != reply_start && frame.front() != identification_start) {
    return frame_error(Errc::invalid_frame, "a reply starts with '!' or '%', got " + quote(frame));
  }
  if (Status printable = detail::check_printable(frame); !printable) return std::move(printable).error();
  if (frame.front() == identification_start) return parse_identification_reply(frame);
  // Only stream records are all digits: every reply has a command of letters (L1).
  if (digits_only(frame.substr(1))) return parse_stream_record(frame);
  return parse_addressed_reply(frame);
}

}  // namespace

Reply Reply::echo(const Request& request) noexcept {
  Reply reply;
  reply.kind = ReplyKind::echo;
  reply.address = request.address;
  reply.command = request.command;
  reply.parameter = request.parameter;
  reply.value = request.value;
  return reply;
}

Reply Reply::parameter_value(std::uint8_t address, std::uint8_t parameter, std::uint8_t value) noexcept {
  Reply reply;
  reply.kind = ReplyKind::parameter_value;
  reply.address = address;
  reply.command = CommandId::read_parameter;
  reply.parameter = parameter;
  reply.value = value;
  return reply;
}

Reply Reply::result_of(std::uint8_t address, CommandId command, ResultCode code) noexcept {
  Reply reply;
  reply.kind = ReplyKind::result;
  reply.address = address;
  reply.command = command;
  reply.result = code;
  return reply;
}

Reply Reply::identification_of(std::uint8_t address, const Identification& identification) noexcept {
  Reply reply;
  reply.kind = ReplyKind::identification;
  reply.address = address;
  reply.command = CommandId::identification;
  reply.identification = identification;
  return reply;
}

Reply Reply::stream_record(ResultCode code) noexcept {
  Reply reply;
  reply.kind = ReplyKind::stream_record;
  reply.command = CommandId::start_stream;
  reply.result = code;
  return reply;
}

Result<Reply> parse_reply(Bytes frame_bytes) {
  // Stream records straight into their Reply: no Result<ResultCode> or second
  // Reply (it holds an Identification) for every 6-byte record.
  // Returned by name on every path, so it is built in the caller's slot.
  // Copied from a finished blank: built field by field on the stack and then
  // copied, a Reply stalled on store forwarding.
  Result<Reply> reply = blank_reply;
  if (std::uint16_t code = 0;
      frame_bytes.size() == detail::stream_record_length && detail::read_good_stream_record(frame_bytes.data(), code)) {
    reply->kind = ReplyKind::stream_record;
    reply->command = CommandId::start_stream;
    reply->result = classify_result_code(code);
  } else {
    reply = parse_any_reply(frame_bytes);
  }
  return reply;
}

Result<Reply> parse_reply_line(Bytes line) {
  const FrameScan scan = scan_reply_frame(line);
  if (scan.status == FrameStatus::complete && scan.consumed == line.size()) return parse_reply(scan.frame);
  if (scan.status == FrameStatus::complete) {
    return frame_error(Errc::overlong, "bytes after the CR of " + quote(as_text(line)));
  }
  if (scan.status == FrameStatus::need_more) {
    return frame_error(Errc::truncated, quote(as_text(line)) + " does not end with CR");
  }
  return frame_error(Errc::invalid_frame,
                     std::string(scan.reason != nullptr ? scan.reason : "line ending before the frame") + " in " +
                         quote(as_text(line)));
}

Result<FrameText> encode_reply(const Reply& reply) {
  FrameText out;
  if (reply.kind == ReplyKind::stream_record) {
    if (!valid_code(reply.result.value)) {
      return frame_error(Errc::out_of_range, "result code " + std::to_string(reply.result.value) + " is invalid (L7)");
    }
    out.push_back(reply_start);
    detail::append_result_code(out, reply.result.value);
    out.push_back(frame_terminator);
    return out;
  }
  if (Status from = check_reply_address(reply.address); !from) return std::move(from).error();
  if (!detail::valid_command(reply.command)) return frame_error(Errc::unknown_command, "no such command id");
  const CommandInfo& info = command_info(reply.command);

  if (reply.kind == ReplyKind::identification) {
    if (info.response != ResponseForm::identification) {
      return frame_error(Errc::wrong_form, "an identification reply must carry the ID command");
    }
    auto field = encode_identification_field(reply.identification);
    if (!field) return std::move(field).error();
    out.push_back(identification_start);
    detail::append_hex_byte(out, reply.address);
    out.append(field->view());
    out.push_back(frame_terminator);
    return out;
  }

  const ResponseForm wanted = reply.kind == ReplyKind::echo              ? ResponseForm::echo
                              : reply.kind == ReplyKind::parameter_value ? ResponseForm::parameter_value
                                                                         : ResponseForm::result;
  if (info.response != wanted) {
    return frame_error(Errc::wrong_form,
                       std::string(info.code) + " is not answered with this kind of reply (table 9.1)");
  }
  out.push_back(reply_start);
  detail::append_hex_byte(out, reply.address);
  out.append(info.code);
  if (reply.kind == ReplyKind::result) {
    if (!valid_code(reply.result.value)) {
      return frame_error(Errc::out_of_range, "result code " + std::to_string(reply.result.value) + " is invalid (L7)");
    }
    detail::append_result_code(out, reply.result.value);
  } else if (reply_argument_length(info) == 4) {
    detail::append_hex_byte(out, reply.parameter);
    detail::append_hex_byte(out, reply.value);
  }
  out.push_back(frame_terminator);
  return out;
}

Status check_reply_answers(const Request& request, const Reply& reply) {
  if (!detail::valid_command(request.command)) return frame_error(Errc::unknown_command, "no such command id");
  const CommandInfo& info = command_info(request.command);
  if (!request.expects_reply()) {
    return frame_error(Errc::wrong_form, std::string(info.code) + " sent to 00 gets no reply (table 9.1 note 2)");
  }
  if (info.response == ResponseForm::stream) {
    if (reply.kind != ReplyKind::stream_record) {
      return frame_error(Errc::wrong_form, "ST is answered by stream records '!ddddd'");
    }
    return ok_status();
  }
  if (reply.kind == ReplyKind::stream_record) {
    return frame_error(Errc::wrong_form, "a stream record does not answer " + std::string(info.code));
  }
  if (reply.address != request.address) {
    return frame_error(Errc::wrong_form, "reply from address " + text::hex_byte(reply.address) + " to a request for " +
                                             text::hex_byte(request.address));
  }
  if (reply.command != request.command) {
    return frame_error(Errc::wrong_form, "reply " + std::string(command_info(reply.command).code) + " to a " +
                                             std::string(info.code) + " request");
  }
  if ((request.command == CommandId::read_parameter || request.command == CommandId::write_parameter) &&
      reply.parameter != request.parameter) {
    return frame_error(Errc::wrong_form, "reply for parameter " + text::hex_byte(reply.parameter) +
                                             " to a request for parameter " + text::hex_byte(request.parameter));
  }
  if (request.command == CommandId::write_parameter && reply.value != request.value) {
    return frame_error(Errc::wrong_form, "parameter " + text::hex_byte(request.parameter) + " written as " +
                                             text::hex_byte(request.value) + " but echoed as " +
                                             text::hex_byte(reply.value));
  }
  return ok_status();
}

}  // namespace rangekit::ls5
