// The ULS model's §8 commands: one handler per command id, the dispatch, and the commands
// that act on the unit (start, stop, measure, pointer) or describe it (version, status).
#include "rangekit/uls/emulator/firmware.hpp"

#include <array>

#include "rangekit/sim/handler_table.hpp"
#include "uls/emulator/command_handlers.hpp"

namespace rangekit::uls::emulator {

Firmware::CommandHandler Firmware::handler(CommandId id) noexcept {
  using Id = CommandId;
  // In CommandId's order, as the codec's table: a row is found by its id.
  static constexpr std::array<sim::HandlerRow<CommandId, CommandHandler>, command_count> rows{{
      {Id::dither, &Firmware::handle_flag<&Settings::dither>},
      {Id::measure, &Firmware::handle_measure},
      {Id::version, &Firmware::handle_version},
      {Id::status, &Firmware::handle_status},
      {Id::autostart, &Firmware::handle_flag<&Settings::autostart>},
      {Id::start, &Firmware::handle_start},
      {Id::stop, &Firmware::handle_stop},
      {Id::pointer_autostart, &Firmware::handle_flag<&Settings::pointer_autostart>},
      {Id::pointer, &Firmware::handle_pointer},
      {Id::save, &Firmware::handle_save},
      {Id::current_loop, &Firmware::handle_flag<&Settings::current_loop>},
      {Id::averaging_weight, &Firmware::handle_averaging_weight},
      {Id::baud, &Firmware::handle_baud},
      {Id::bin_size, &Firmware::handle_count<&Settings::bin_size>},
      {Id::bin_threshold, &Firmware::handle_count<&Settings::bin_hits>},
      {Id::continuous, &Firmware::handle_flag<&Settings::continuous>},
      {Id::cooperative_filter, &Firmware::handle_flag<&Settings::cooperative_filter>},
      {Id::display, &Firmware::handle_choice<&Settings::display, &to_display_mode>},
      {Id::fault_current, &Firmware::handle_decimal<&Settings::fault_current_ma>},
      {Id::fault_timeout, &Firmware::handle_decimal<&Settings::fault_timeout_s>},
      {Id::long_gate, &Firmware::handle_distance<&Settings::long_gate_m>},
      {Id::mode, &Firmware::handle_choice<&Settings::mode, &to_mode>},
      {Id::output_port, &Firmware::handle_choice<&Settings::output_port, &to_output_port>},
      {Id::units, &Firmware::handle_choice<&Settings::units, &to_units>},
      {Id::power, &Firmware::handle_choice<&Settings::power, &to_power_level>},
      {Id::prf, &Firmware::handle_prf},
      {Id::ppm, &Firmware::handle_ppm},
      {Id::range_at_20ma, &Firmware::handle_loop_range},
      {Id::range_at_4ma, &Firmware::handle_loop_range},
      {Id::termination, &Firmware::handle_flag<&Settings::termination>},
      {Id::short_gate, &Firmware::handle_distance<&Settings::short_gate_m>},
      {Id::time_between_events, &Firmware::handle_flag<&Settings::time_between_events>},
      {Id::trip_point, &Firmware::handle_distance<&Settings::trip_point_m>},
      {Id::trip_timeout, &Firmware::handle_trip_timeout},
      {Id::address, &Firmware::handle_address},
      {Id::offset, &Firmware::handle_distance<&Settings::offset_m>},
  }};
  static_assert(sim::in_id_order(rows), "ULS handler rows out of CommandId order");
  return rows[static_cast<std::size_t>(id)].handle;
}

void Firmware::execute(std::size_t port, Address to, bool silent, const CommandInfo& command, RequestForm form,
                       const FrameView& frame, Nanos now) {
  const Request request{port, to, silent, command, form, frame.fields(), now};
  (this->*handler(command.id))(request);
}

void Firmware::answer_ok(const Request& request) {
  reply(request.port, request.silent, encode_ok(request.to), request.now);
}

void Firmware::answer_error(const Request& request, int number) {
  reply(request.port, request.silent, encode_error_reply(request.to, number), request.now);
}

void Firmware::answer(const Request& request, std::initializer_list<std::string_view> values) {
  reply_values(request.port, request.to, request.silent, request.command.mnemonic, values, request.now);
}

void Firmware::handle_start(const Request& request) {
  start_measuring(request.now);
  answer_ok(request);
}

void Firmware::handle_stop(const Request& request) {
  if (!measuring_) return answer_error(request, 86);  // Instrument Not Measuring (§10, U43)
  stop_measuring();
  answer_ok(request);
}

void Firmware::handle_measure(const Request& request) {
  const Nanos now = request.now;
  if (request.silent) {
    if (!measuring_) start_measuring(now);
    return;
  }
  if (settings_.mode == Mode::look_down) {
    // §8 Get Measurement: "Varies with measurement mode". Look down has a state at every
    // moment (the trip line), so a poll is answered at once with it, never queued (U70-U72).
    if (!measuring_) start_measuring(now);  // §2 ULS Autostart
    reply(request.port, false, encode_measurement(request.to, look_down_state()), now);
    return;
  }
  if (!measuring_) {
    start_measuring(now);  // §2 ULS Autostart: Get Measurement starts the unit
    polls_.push_back({request.port, request.to});
    return;
  }
  if (latest_.empty()) {
    polls_.push_back({request.port, request.to});
    return;
  }
  for (const auto& reading : latest_) reply(request.port, false, encode_measurement(request.to, reading), now);
}

void Firmware::handle_pointer(const Request& request) {
  pointer_ = request.fields[0] == "1";
  answer_ok(request);
}

void Firmware::handle_version(const Request& request) {
  answer(request, {"ULS emulator rangekit 1.0 protocol 0.97", "2026-11-25"});
}

void Firmware::handle_status(const Request& request) {
  answer(request, {std::to_string(wire_value(status_for(measuring_, settings_.mode)))});
}

}  // namespace rangekit::uls::emulator
