// The ULS settings in non-volatile memory: stored by SU (§8), read back at power-up,
// keyed by mnemonic.
#include "rangekit/uls/emulator/firmware.hpp"

#include <type_traits>

#include "uls/emulator/command_handlers.hpp"

namespace rangekit::uls::emulator {

nlohmann::json Settings::to_json() const {
  return {{"MM", wire_value(mode)},
          {"PF", prf},
          {"PO", ppm},
          {"AW", averaging_weight},
          {"DD", dither},
          {"BS", bin_size},
          {"BH", bin_hits},
          {"CO", continuous},
          {"FL", cooperative_filter},
          {"DM", wire_value(display)},
          {"AF", fault_current_ma},
          {"AT", fault_timeout_s},
          {"LG", long_gate_m},
          {"SG", short_gate_m},
          {"MO", wire_value(output_port)},
          {"MU", wire_value(units)},
          {"PL", wire_value(power)},
          {"AH", range_at_20ma_m},
          {"AL", range_at_4ma_m},
          {"TE", termination},
          {"TB", time_between_events},
          {"TP", trip_point_m},
          {"TT", trip_timeout_pulses},
          {"UA", address},
          {"OF", offset_m},
          {"MA", autostart},
          {"PA", pointer_autostart},
          {"CL", current_loop},
          {"BR", baud},
          {"min_pulse_width_ns", min_pulse_width_ns}};
}

Settings Settings::from_json(const nlohmann::json& memory, const Settings& defaults) {
  Settings s = defaults;
  auto get = [&](const char* key, auto& field) {
    if (memory.contains(key)) field = memory.at(key).get<std::decay_t<decltype(field)>>();
  };
  std::uint8_t mode = wire_value(s.mode), display = wire_value(s.display), port = wire_value(s.output_port),
               units = wire_value(s.units), power = wire_value(s.power);
  get("MM", mode);
  get("DM", display);
  get("MO", port);
  get("MU", units);
  get("PL", power);
  s.mode = to_mode(mode).value_or(defaults.mode);
  s.display = to_display_mode(display).value_or(defaults.display);
  s.output_port = to_output_port(port).value_or(defaults.output_port);
  s.units = to_units(units).value_or(defaults.units);
  s.power = to_power_level(power).value_or(defaults.power);
  get("PF", s.prf);
  get("PO", s.ppm);
  get("AW", s.averaging_weight);
  get("DD", s.dither);
  get("BS", s.bin_size);
  get("BH", s.bin_hits);
  get("CO", s.continuous);
  get("FL", s.cooperative_filter);
  get("AF", s.fault_current_ma);
  get("AT", s.fault_timeout_s);
  get("LG", s.long_gate_m);
  get("SG", s.short_gate_m);
  get("AH", s.range_at_20ma_m);
  get("AL", s.range_at_4ma_m);
  get("TE", s.termination);
  get("TB", s.time_between_events);
  get("TP", s.trip_point_m);
  get("TT", s.trip_timeout_pulses);
  get("UA", s.address);
  get("OF", s.offset_m);
  get("MA", s.autostart);
  get("PA", s.pointer_autostart);
  get("CL", s.current_loop);
  get("BR", s.baud);
  get("min_pulse_width_ns", s.min_pulse_width_ns);
  return s;
}

void Firmware::handle_save(const Request& request) {
  auto memory = settings_.to_json();
  if (store_.save(memory)) {
    memory_ = std::move(memory);  // the next power-up reads it, with or without a file behind it
    return answer_ok(request);
  }
  answer_error(request, 10);  // "☒ must be resolved by LTI": memory failure
}

}  // namespace rangekit::uls::emulator
