#include "rangekit/ls5/request.hpp"

#include <string>

#include "ls5/frame_fields.hpp"
#include "ls5/messages.hpp"

namespace rangekit::ls5 {
namespace {

const char* argument_description(RequestForm form) noexcept {
  switch (form) {
    case RequestForm::no_argument:
      return "no argument";
    case RequestForm::parameter_address:
      return "a parameter address (aa)";
    case RequestForm::address_and_value:
      return "a parameter address and a value (aadd)";
  }
  return "";
}

// Table 9.1 note 1 (conformance L15).
Status check_broadcast(std::uint8_t address, const CommandInfo& command) {
  if (address == broadcast_address && !command.broadcast_allowed) {
    return detail::frame_error(
        Errc::wrong_form, std::string(command.code) + " cannot be sent to the broadcast address 00 (table 9.1 note 1)");
  }
  return ok_status();
}

}  // namespace

bool Request::expects_reply() const noexcept {
  return !(is_broadcast() && detail::valid_command(command) && command_info(command).silent_on_broadcast);
}

Result<Request> parse_request(Bytes frame_bytes) {
  const std::string_view frame = as_text(frame_bytes);
  if (frame.empty()) return detail::frame_error(Errc::truncated, "empty request");
  if (frame.front() != request_start) {
    return detail::frame_error(Errc::invalid_frame, "a request starts with '#', got " + detail::quote(frame));
  }
  if (Status printable = detail::check_printable(frame); !printable) return std::move(printable).error();

  auto address = detail::parse_address(frame);
  if (!address) return std::move(address).error();
  auto command = detail::parse_command(frame);
  if (!command) return std::move(command).error();
  const CommandInfo& info = **command;

  Status length = detail::check_argument_length(frame, info, request_argument_length(info.request),
                                                argument_description(info.request));
  if (!length) return std::move(length).error();

  Request request{*address, info.id, 0, 0};
  const std::size_t at = 3 + info.code.size();
  if (info.request != RequestForm::no_argument) {
    auto parameter = detail::parse_hex_byte(frame, at, "parameter address");
    if (!parameter) return std::move(parameter).error();
    request.parameter = *parameter;
  }
  if (info.request == RequestForm::address_and_value) {
    auto value = detail::parse_hex_byte(frame, at + 2, "parameter value");
    if (!value) return std::move(value).error();
    request.value = *value;
  }
  if (Status broadcast = check_broadcast(request.address, info); !broadcast) return std::move(broadcast).error();
  return request;
}

Result<Request> parse_request_line(Bytes line) {
  const FrameScan scan = scan_request_frame(line);
  if (scan.status == FrameStatus::complete && scan.consumed == line.size()) return parse_request(scan.frame);
  if (scan.status == FrameStatus::complete) {
    return detail::frame_error(Errc::overlong, "bytes after the CR of " + detail::quote(as_text(line)));
  }
  if (scan.status == FrameStatus::need_more) {
    return detail::frame_error(Errc::truncated, detail::quote(as_text(line)) + " does not end with CR");
  }
  return detail::frame_error(
      Errc::invalid_frame, std::string(scan.reason != nullptr ? scan.reason : "line ending before the frame") + " in " +
                               detail::quote(as_text(line)));
}

Result<FrameText> encode_request(const Request& request) {
  if (!detail::valid_command(request.command)) return detail::frame_error(Errc::unknown_command, "no such command id");
  const CommandInfo& info = command_info(request.command);
  if (Status broadcast = check_broadcast(request.address, info); !broadcast) return std::move(broadcast).error();
  FrameText out;
  out.push_back(request_start);
  detail::append_hex_byte(out, request.address);
  out.append(info.code);
  if (info.request != RequestForm::no_argument) detail::append_hex_byte(out, request.parameter);
  if (info.request == RequestForm::address_and_value) detail::append_hex_byte(out, request.value);
  out.push_back(frame_terminator);
  return out;
}

}  // namespace rangekit::ls5
