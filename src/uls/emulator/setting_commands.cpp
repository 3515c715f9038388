// The ULS settings commands with rules of their own: values that depend on each other
// (AW and PO, AH and AL), one value per mode (PF, PO), a port's speed (BR), TT and UA.
#include "rangekit/uls/emulator/firmware.hpp"

#include <algorithm>

#include "uls/emulator/command_handlers.hpp"

namespace rangekit::uls::emulator {

void Firmware::handle_averaging_weight(const Request& request) {
  if (request.get()) return answer(request, {std::to_string(settings_.averaging_weight)});
  const std::uint32_t weight = parse_unsigned(request.fields[0]);
  if (auto v = check_ppm_against_weight(settings_.ppm[0], weight); !v.ok()) return answer_error(request, v.error);
  settings_.averaging_weight = weight;
  answer_ok(request);
}

void Firmware::handle_ppm(const Request& request) {
  const auto fields = request.fields;
  if (request.get()) return answer(request, {std::to_string(settings_.ppm[0]), std::to_string(settings_.ppm[1])});
  // §2 "Pulses/Measure ... not available in the Look Down Mode": one value names no PPM there (U79).
  if (fields.size() == 1 && settings_.mode == Mode::look_down) {
    return answer_error(request, error_number::invalid_for_mode);
  }
  auto ppm = settings_.ppm;
  if (fields.size() == 2) {
    ppm = {parse_unsigned(fields[0]), parse_unsigned(fields[1])};
  } else {
    ppm[settings_.mode == Mode::binning ? 1 : 0] = parse_unsigned(fields[0]);
  }
  if (auto v = check_ppm_against_weight(ppm[0], settings_.averaging_weight); !v.ok()) {
    return answer_error(request, v.error);
  }
  settings_.ppm = ppm;
  answer_ok(request);
}

void Firmware::handle_prf(const Request& request) {
  const auto fields = request.fields;
  if (request.get()) {
    return answer(request, {std::to_string(settings_.prf[0]), std::to_string(settings_.prf[1]),
                            std::to_string(settings_.prf[2])});
  }
  if (fields.size() == 3) {
    for (std::size_t i = 0; i < 3; ++i) settings_.prf[i] = parse_unsigned(fields[i]);
  } else {
    settings_.prf[static_cast<std::size_t>(wire_value(settings_.mode) - 1)] = parse_unsigned(fields[0]);
  }
  answer_ok(request);
}

void Firmware::handle_baud(const Request& request) {
  const auto fields = request.fields;
  const std::size_t which = fields[0] == "1" ? 1 : 0;
  if (request.get()) return answer(request, {fields[0], std::to_string(settings_.baud[which])});
  answer_ok(request);
  // The port switches once this $OK has left the port it answers on (drain, U36).
  auto& target = ports_[which];
  target.pending_baud = parse_unsigned(fields[1]);
  target.pending_at = std::max(request.now, ports_[request.port].pacer.idle_at(request.now));
  target.pending_port = request.port;
}

void Firmware::handle_loop_range(const Request& request) {
  const CommandInfo& command = request.command;
  const Units units = settings_.units;
  double& field = command.id == CommandId::range_at_20ma ? settings_.range_at_20ma_m : settings_.range_at_4ma_m;
  if (request.get()) return answer(request, {distance_text(field, units)});
  const double metres = distance_to_metres(parse_number(request.fields[0]), units, command.min, command.max);  // U76
  const double low = command.id == CommandId::range_at_4ma ? metres : settings_.range_at_4ma_m;
  const double high = command.id == CommandId::range_at_20ma ? metres : settings_.range_at_20ma_m;
  if (auto v = check_current_loop_range(low, high); !v.ok()) return answer_error(request, v.error);
  field = metres;
  answer_ok(request);
}

void Firmware::handle_trip_timeout(const Request& request) {
  if (request.get()) return answer(request, {to_hex_text(settings_.trip_timeout_pulses).view()});
  settings_.trip_timeout_pulses = parse_trip_timeout(request.fields[0]).value_or(settings_.trip_timeout_pulses);
  answer_ok(request);
}

void Firmware::handle_address(const Request& request) {
  if (request.get()) {
    if (settings_.address == 0) return answer_error(request, 82);  // U3
    return answer(request, {std::to_string(unit_address_value(settings_.address))});
  }
  answer_ok(request);  // the reply still carries the old address
  settings_.address = static_cast<std::uint8_t>(request.fields[0][0]);
}

}  // namespace rangekit::uls::emulator
