#include <fmt/core.h>

#include "rangekit/uls/commands.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/reply.hpp"
#include "uls/cli/uls_cli.hpp"

namespace rangekit::cli {
namespace {

std::string who(const uls::Address& address) {
  if (!address.addressed) return "";
  if (address.is_broadcast()) return fmt::format("broadcast 0x{:02X}: ", address.byte);
  const char c = static_cast<char>(address.byte);
  if (c >= 0x30 && c < 0x7f) return fmt::format("unit '{}' (0x{:02X}): ", c, address.byte);
  return fmt::format("unit 0x{:02X}: ", address.byte);
}

// "Set/Get Measurement Mode" -> "Measurement Mode": the verb is already said.
std::string_view short_title(const uls::CommandInfo& command) {
  std::string_view title = command.title;
  for (const std::string_view prefix : {"Set/Get ", "Get "}) {
    if (title.substr(0, prefix.size()) == prefix) title.remove_prefix(prefix.size());
  }
  return title;
}

std::string values_text(const uls::CommandInfo& command, std::span<const std::string_view> values) {
  std::string text;
  for (const auto value : values) {
    if (!text.empty()) text += ", ";
    text += std::string(value);
    std::uint32_t number = 0;
    bool numeric = !value.empty();
    for (const char c : value) {
      if (c < '0' || c > '9')
        numeric = false;
      else
        number = number * 10 + static_cast<std::uint32_t>(c - '0');
    }
    if (numeric && !command.value_names.empty()) {
      const auto name = command.value_name(number);
      if (!name.empty()) text += fmt::format(" ({})", name);
    }
  }
  return text;
}

std::string describe_request(const uls::FrameView& frame) {
  const auto* command = uls::find_command(frame.mnemonic);
  if (command == nullptr) return fmt::format("{}unknown command '{}'", who(frame.address), frame.mnemonic);
  const auto form = uls::request_form(*command, frame.field_count);
  if (!form.verdict.ok()) {
    return fmt::format("{}{}: a unit answers error {}", who(frame.address), short_title(*command), form.verdict.error);
  }
  switch (form.form) {
    case uls::RequestForm::get:
      return fmt::format("{}get {}{}", who(frame.address), short_title(*command),
                         frame.field_count > 0 ? " for " + values_text(*command, frame.fields()) : "");
    case uls::RequestForm::set: {
      const auto verdict = uls::validate_request(*command, frame.fields());
      std::string text = fmt::format("{}set {} = {}", who(frame.address), short_title(*command),
                                     values_text(*command, frame.fields()));
      if (!verdict.ok()) text += fmt::format("  [a unit answers error {}]", verdict.error);
      return text;
    }
    case uls::RequestForm::action:
      return fmt::format("{}{}", who(frame.address), command->title);
  }
  return "";
}

std::string describe_measurement(const uls::Measurement& measurement) {
  const std::string prefix = who(measurement.source);
  if (const auto* averaging = std::get_if<uls::AveragingReading>(&measurement.reading)) {
    std::string text = prefix + "averaging:";
    if (averaging->range) text += fmt::format(" {:.3f} m", averaging->range->metres);
    if (averaging->pulse_width_ps) text += fmt::format(" pulse width {:.3f} ns", *averaging->pulse_width_ns());
    return text;
  }
  if (const auto* target = std::get_if<uls::BinningTarget>(&measurement.reading)) {
    return fmt::format("{}binning target {} of {}: {:.3f} m, strength {}", prefix, target->index + 1, target->count,
                       target->range.metres, target->strength);
  }
  if (const auto* look_down = std::get_if<uls::LookDownReading>(&measurement.reading)) {
    return prefix + (look_down->present ? "look down: ON (presence)" : "look down: OFF (reference only)");
  }
  if (const auto* event = std::get_if<uls::TimeBetweenEvents>(&measurement.reading)) {
    switch (event->kind) {
      case uls::TimeBetweenEvents::Kind::no_presence:
        return prefix + "time between events: no presence";
      case uls::TimeBetweenEvents::Kind::overflow:
        return prefix + "time between events: over 65535 pulses (0000)";
      case uls::TimeBetweenEvents::Kind::pulses:
        return fmt::format("{}time between events: {} pulses ({:.3f} s at 3000 Hz PRF)", prefix, event->pulses,
                           event->pulses / 3000.0);
    }
  }
  const auto& error = std::get<uls::MeasurementError>(measurement.reading);
  const auto* info = uls::find_error(error.number);
  return fmt::format("{}measurement error {}: {}", prefix, error.number,
                     info ? info->display : "not in the ULS's error table");
}

std::string describe_reply(const uls::FrameView& frame, const uls::MeasurementContext& context) {
  if (frame.kind == uls::FrameKind::time_between_events || frame.is("BM")) {
    uls::MeasurementContext use = context;
    if (frame.kind == uls::FrameKind::time_between_events) {
      use.mode = uls::Mode::look_down;
      use.time_between_events = true;
    }
    auto measurement = uls::decode_measurement(frame, use);
    if (!measurement) return "not a measurement: " + measurement.error().message;
    return describe_measurement(*measurement);
  }
  auto reply = uls::decode_reply(frame, context.units);
  if (!reply) return "not a reply: " + reply.error().message;
  switch (reply->kind) {
    case uls::ReplyKind::ok:
      return who(reply->source) + "accepted (OK)";
    case uls::ReplyKind::error:
      return fmt::format("{}error {}: {} (display \"{}\")", who(reply->source), reply->error_number,
                         reply->error ? reply->error->explanation : "not in the ULS's error table",
                         reply->error ? reply->error->display : "");
    case uls::ReplyKind::value:
      return fmt::format("{}{} = {}", who(reply->source), short_title(*reply->command),
                         values_text(*reply->command, reply->values()));
  }
  return "";
}

}  // namespace

std::string describe_uls_frame(Bytes frame, Direction direction, const uls::MeasurementContext& context) {
  auto parsed = uls::parse_frame(frame);
  if (!parsed) return "rejected: " + parsed.error().message;
  return direction == Direction::to_device ? describe_request(*parsed) : describe_reply(*parsed, context);
}

}  // namespace rangekit::cli
