#include <fmt/core.h>

#include "ls5/cli/ls5_cli.hpp"
#include "rangekit/ls5/parameters.hpp"
#include "rangekit/ls5/request.hpp"
#include "rangekit/ls5/result_code.hpp"

namespace rangekit::cli {
namespace {

std::string sensor(std::uint8_t address) {
  return address == ls5::broadcast_address ? "broadcast 00: " : fmt::format("sensor {:02X}: ", address);
}

std::string parameter_text(std::uint8_t address, std::uint8_t value) {
  const auto* parameter = ls5::find_parameter(address);
  if (parameter == nullptr) return fmt::format("parameter {:02X} (not in table 9.2) = {:02X}", address, value);
  std::string text = fmt::format("parameter {:02X} ({}) = {:02X}", address, parameter->name, value);
  for (const auto& named : parameter->named_values) {
    if (named.value == value) text += fmt::format(" ({})", named.meaning);
  }
  return text;
}

std::string code_text(const ls5::ResultCode& code, double range_mm) {
  switch (code.kind) {
    case ls5::CodeKind::no_measurement_yet:
      return "65534: no measurement yet";
    case ls5::CodeKind::no_signal:
      return "65535: no signal";
    case ls5::CodeKind::result:
      break;
  }
  if (range_mm <= 0) return fmt::format("code {}", code.value);
  return fmt::format("code {} = {:.4f} mm from the start of the range", code.value,
                     ls5::distance_mm(code.value, range_mm));
}

}  // namespace

std::string describe_ls5_frame(Bytes frame, Direction direction, double range_mm) {
  if (direction == Direction::to_device) {
    auto request = ls5::parse_request(frame);
    if (!request) return "rejected: " + request.error().message;
    const auto& info = ls5::command_info(request->command);
    std::string text = sensor(request->address) + std::string(info.name);
    if (request->command == ls5::CommandId::read_parameter) {
      const auto* parameter = ls5::find_parameter(request->parameter);
      text += fmt::format(" {:02X} ({})", request->parameter, parameter ? parameter->name : "not in table 9.2");
    }
    if (request->command == ls5::CommandId::write_parameter)
      text += ": " + parameter_text(request->parameter, request->value);
    if (request->is_broadcast()) text += " (no reply)";
    return text;
  }
  auto reply = ls5::parse_reply(frame);
  if (!reply) return "rejected: " + reply.error().message;
  switch (reply->kind) {
    case ls5::ReplyKind::stream_record:
      return "stream record: " + code_text(reply->result, range_mm);
    case ls5::ReplyKind::result:
      return sensor(reply->address) + std::string(ls5::command_info(reply->command).name) + ": " +
             code_text(reply->result, range_mm);
    case ls5::ReplyKind::parameter_value:
      return sensor(reply->address) + parameter_text(reply->parameter, reply->value);
    case ls5::ReplyKind::identification: {
      const auto& id = reply->identification;
      return fmt::format("{}identification: version {}, lower boundary {} mm, range {} mm, serial {}",
                         sensor(reply->address), std::string_view(id.version_text.view()), id.lower_boundary_mm,
                         id.range_mm, id.serial_number);
    }
    case ls5::ReplyKind::echo: {
      std::string text = sensor(reply->address) + "done: " + std::string(ls5::command_info(reply->command).name);
      // A write's echo repeats what was written (§9.4): said again, so a reply reads alone.
      if (reply->command == ls5::CommandId::write_parameter)
        text += ": " + parameter_text(reply->parameter, reply->value);
      return text;
    }
  }
  return "";
}

}  // namespace rangekit::cli
