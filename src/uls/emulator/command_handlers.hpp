// What the ULS command handlers share: the request, value text, and the handlers of the
// plain settings, templates here so that the handler table can instantiate one per setting.
#pragma once
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>

#include "rangekit/uls/emulator/firmware.hpp"

namespace rangekit::uls::emulator {

// A request that passed its row's checks (form, values, measuring), ready to act on.
struct Firmware::Request {
  std::size_t port;  // the port it came on, where the answer goes
  Address to;        // the address the answer carries
  bool silent;       // a broadcast: acted on, never answered (U4)
  const CommandInfo& command;
  RequestForm form;
  std::span<const std::string_view> fields;
  Nanos now;

  [[nodiscard]] bool get() const noexcept { return form == RequestForm::get; }
};

// A decimal as the unit prints it: no trailing zeros or point.
inline std::string number_text(double value) {
  std::string text = std::to_string(value);  // fixed, 6 decimals
  while (!text.empty() && text.back() == '0') text.pop_back();
  if (!text.empty() && text.back() == '.') text.pop_back();
  return text;
}

inline std::string distance_text(double metres, Units units) {
  auto field = format_distance(from_metres(metres, units), units);
  return field ? std::string(field->view()) : std::string("0");
}

// The request's values already passed validate_request, so they parse.
inline double parse_number(std::string_view text) { return std::strtod(std::string(text).c_str(), nullptr); }

inline std::uint32_t parse_unsigned(std::string_view text) {
  return static_cast<std::uint32_t>(std::strtoul(std::string(text).c_str(), nullptr, 10));
}

template <bool Settings::*field>
void Firmware::handle_flag(const Request& request) {
  if (request.get()) return answer(request, {settings_.*field ? "1" : "0"});
  settings_.*field = request.fields[0] == "1";
  answer_ok(request);
}

// A whole number in decimal (BH, BS).
template <auto field>
void Firmware::handle_count(const Request& request) {
  auto& setting = settings_.*field;
  if (request.get()) return answer(request, {std::to_string(setting)});
  setting = static_cast<std::remove_reference_t<decltype(setting)>>(parse_unsigned(request.fields[0]));
  answer_ok(request);
}

// One of an enumeration's wire values; `convert` maps the number to it (DM, MM, MO, MU, PL).
template <auto field, auto convert>
void Firmware::handle_choice(const Request& request) {
  auto& setting = settings_.*field;
  if (request.get()) return answer(request, {std::to_string(wire_value(setting))});
  setting = convert(parse_unsigned(request.fields[0])).value_or(setting);
  answer_ok(request);
}

// A decimal in fixed units (AF in mA, AT in seconds).
template <double Settings::*field>
void Firmware::handle_decimal(const Request& request) {
  if (request.get()) return answer(request, {number_text(settings_.*field)});
  settings_.*field = parse_number(request.fields[0]);
  answer_ok(request);
}

// A distance in the units MU sets, kept in metres (LG, SG, TP, OF).
template <double Settings::*field>
void Firmware::handle_distance(const Request& request) {
  const Units units = settings_.units;
  if (request.get()) return answer(request, {distance_text(settings_.*field, units)});
  const CommandInfo& command = request.command;
  settings_.*field = distance_to_metres(parse_number(request.fields[0]), units, command.min, command.max);  // U76
  answer_ok(request);
}

}  // namespace rangekit::uls::emulator
