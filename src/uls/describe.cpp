#include "rangekit/uls/describe.hpp"

#include <cmath>
#include <cstdio>

#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/formulas.hpp"

namespace rangekit::uls {

std::string decimal_text(double value) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.3f", value);
  std::string text = buffer;
  while (!text.empty() && text.back() == '0') text.pop_back();
  if (!text.empty() && text.back() == '.') text.pop_back();
  if (text == "-0") text = "0";
  return text;
}

namespace {

// §9 Baud Rate Choices: "1200, 2400, ... 230400".
std::string baud_list() {
  std::string text;
  for (const std::uint32_t baud : baud_choices()) text += (text.empty() ? "" : ", ") + std::to_string(baud);
  return text;
}

std::string port_list(const CommandInfo& command) {
  std::string text;
  for (const ValueName& entry : command.value_names)
    text += (text.empty() ? "" : ", ") + std::to_string(entry.value) + " " + std::string(entry.name);
  return text;
}

}  // namespace

std::string allowed_values(const CommandInfo& command, Units units) {
  // BR's value names are its ports; its values are a port and a baud.
  if (command.kind == ValueKind::baud_with_port)
    return "port " + port_list(command) + ", then a baud of " + baud_list();
  if (!command.value_names.empty()) {
    // As typed: the name (its code in brackets), "look-down (3)".
    std::string text;
    for (const ValueName& entry : command.value_names) {
      if (!text.empty()) text += ", ";
      text += value_key(entry.name) + " (" + std::to_string(entry.value) + ")";
    }
    return text;
  }
  switch (command.kind) {
    case ValueKind::distance:
    case ValueKind::signed_distance:
      return decimal_text(from_metres(command.min, units)) + ".." + decimal_text(from_metres(command.max, units)) +
             (units == Units::feet ? " feet" : " metres");
    case ValueKind::hex_pulses:
      return "1 to 8 hex digits (pulses = seconds x 3000)";
    case ValueKind::address_char:
      return "one character 0x30..0xEF ('0'..'9', 'A'..'Z', 'a'..'z', ...)";
    case ValueKind::prf_list:
      return "10..5000 Hz, one value (current mode) or three (averaging, binning, look down)";
    case ValueKind::ppm_list:
      return "1..65535 pulses, one value (current mode) or two (averaging, binning)";
    default:
      return decimal_text(command.min) + ".." + decimal_text(command.max) +
             (command.unit.empty() ? "" : " " + std::string(command.unit));
  }
}

Error device_error(int number, std::string_view context) {
  const ErrorInfo* info = find_error(number);
  std::string text = "device error " + std::to_string(number) + ": " +
                     (info != nullptr ? std::string(info->explanation) : std::string("(not in the ULS's error table)"));
  if (info != nullptr && info->service_required) text += " (must be resolved by LTI)";
  if (!context.empty()) text = std::string(context) + ": " + text;
  Error error = make_error(Errc::device_error, text);
  error.device_code = number;
  return error;
}

Error local_refusal(const CommandInfo& command, std::string_view shown_values, int verdict_error, Units units) {
  const std::string name = std::string(command.cli_name) + " (" + std::string(command.mnemonic) + ")";
  if (shown_values.empty() && !command.has_get())
    return make_error(Errc::wrong_form, name + " cannot be read, only set");
  if (!command.has_set() && !shown_values.empty())
    return make_error(Errc::wrong_form, name + " cannot be set, only read");
  std::string allowed = "allowed: " + allowed_values(command, units);
  if (command.kind == ValueKind::baud_with_port) {
    // U91: a lone value is no port, and a refused baud names the bauds, not the ports.
    if (shown_values.find(',') == std::string_view::npos) {
      return make_error(Errc::out_of_range, name + ": '" + std::string(shown_values) +
                                                "' refused before sending: a baud setting needs the port and the "
                                                "baud (0,115200: configuration port; 1,115200: output port); bauds: " +
                                                baud_list());
    }
    if (verdict_error == error_number::invalid_baud) allowed = "allowed bauds: " + baud_list();
    if (verdict_error == error_number::invalid_port) allowed = "allowed ports: " + port_list(command);
  }
  std::string text = name + ": '" + std::string(shown_values) + "' refused before sending; " + allowed;
  if (const ErrorInfo* info = find_error(verdict_error); info != nullptr && verdict_error != 1)
    text +=
        " (the unit would answer error " + std::to_string(verdict_error) + ", " + std::string(info->explanation) + ")";
  return make_error(Errc::out_of_range, text);
}

}  // namespace rangekit::uls
