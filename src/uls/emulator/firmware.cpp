// The ULS firmware model; see firmware.hpp and docs/emulator-uls.md.
#include "rangekit/sim/uls/firmware.hpp"

#include "rangekit/sim/control_socket.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

namespace rangekit::uls::emulator {
namespace {

constexpr double minimum_range_m = 0.15;        // §9
constexpr double cooperative_range_m = 1700.0;  // §9 reflective sheet, every power level
// §9 maximum ranges by power level (high, medium, low).
constexpr std::array<double, 3> white_range_m{266.0, 228.0, 188.0};  // 90% white
constexpr std::array<double, 3> gray_range_m{133.0, 114.0, 94.0};    // 20% gray
// Single-pulse timing jitter (one sigma) and the time quantum of a pulse (docs/emulator-uls.md).
constexpr double jitter_m = 0.02;
constexpr double cooperative_jitter_m = 0.01;
constexpr double quantum_m = 0.05;
constexpr std::uint32_t dither_cycle = 32;  // §3
constexpr double detect_probability = 0.99;
// The same as a threshold on the engine's raw 64-bit output: no conversion to double per pulse.
constexpr auto detect_threshold = static_cast<std::uint64_t>(detect_probability * 18446744073709551616.0);
// Received pulse widths (U40): about the 8 ns transmit pulse (§3) for a return at the
// detection limit, wider as the signal grows (time over threshold, logarithmic).
constexpr double weakest_width_ns = 4.0;
constexpr double width_ns_per_doubling = 6.0;
constexpr double dust_width_ns = 3.0;   // dust near the unit: a weak, narrow return
constexpr double noise_window_m = 0.5;  // narrowest noise-filter window (U48)
// The §3 binning restart rule: at most this many targets per burst.
constexpr std::size_t restart_targets = max_binning_targets;

std::string number_text(double value) {
  std::string text = std::to_string(value);  // fixed, 6 decimals
  while (!text.empty() && text.back() == '0') text.pop_back();
  if (!text.empty() && text.back() == '.') text.pop_back();
  return text;
}

std::string distance_text(double metres, Units units) {
  auto field = format_distance(from_metres(metres, units), units);
  return field ? std::string(field->view()) : std::string("0");
}

double parse_number(std::string_view text) { return std::strtod(std::string(text).c_str(), nullptr); }

std::uint32_t parse_unsigned(std::string_view text) {
  return static_cast<std::uint32_t>(std::strtoul(std::string(text).c_str(), nullptr, 10));
}

double seconds(Nanos span) { return static_cast<double>(span.count()) / 1e9; }

// Whether a target at `d` can answer at all: beyond the minimum range, inside the short and
// long gates (0 = off) and, with the cooperative filter on, a cooperative target (§8 SG, LG, FL).
bool passes_gates(const Settings& settings, double d, bool cooperative) noexcept {
  if (d < minimum_range_m) return false;
  if (settings.short_gate_m > 0 && d < settings.short_gate_m) return false;
  if (settings.long_gate_m > 0 && d > settings.long_gate_m) return false;
  return !settings.cooperative_filter || cooperative;
}

}  // namespace

// --- Settings in non-volatile memory ---

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

// --- Construction and power ---

Firmware::Firmware(FirmwareOptions options, Nanos now)
    : options_(std::move(options)),
      store_(options_.state_dir, options_.state_key),
      scene_(options_.scene),
      random_(options_.seed) {
  if (options_.address) factory_.address = *options_.address;
  boot(now);
}

void Firmware::boot(Nanos now) {
  settings_ = factory_;
  if (auto memory = store_.load(); memory && memory->has_value()) {
    try {
      settings_ = Settings::from_json(**memory, factory_);
    } catch (const nlohmann::json::exception&) {
      settings_ = factory_;  // unreadable memory: factory defaults
    }
  }
  for (std::size_t i = 0; i < ports_.size(); ++i) {
    ports_[i].input.clear();
    ports_[i].overrun.reset();
    ports_[i].outbox.clear();
    ports_[i].pending_baud.reset();
    ports_[i].last_line_start = Nanos(0);
    ports_[i].pacer = SerialPacer(settings_.baud[i], uls_hundredths_of_bits);
  }
  measuring_ = false;
  latest_.clear();
  polls_.clear();
  last_distance_m_.reset();
  last_error_ = 0;
  error_since_.reset();
  pointer_ = settings_.pointer_autostart;
  last_now_ = now;
  if (settings_.autostart) start_measuring(now);  // §2 ULS Autostart
}

void Firmware::power_cycle(Nanos now) { boot(now); }

std::string Firmware::label() const {
  if (settings_.address == 0) return "ULS (unassigned)";
  return std::string("ULS #") + static_cast<char>(settings_.address);
}

SerialSettings Firmware::port_settings(std::size_t port) const {
  return SerialSettings{settings_.baud[std::min<std::size_t>(port, 1)], Parity::none, 1};
}

// --- Serial side ---

void Firmware::take_until(Port& port, Nanos until) {
  while (port.pacer.next_completion() <= until) {
    const Nanos done = port.pacer.next_completion();
    sent_.clear();  // reused: no allocation per byte
    port.pacer.take_sent(done, sent_);
    const auto index = static_cast<std::size_t>(&port - ports_.data());
    for (const auto value : sent_) port.outbox.push_back(LineByte{done, value, settings_.baud[index]});
  }
}

void Firmware::drain(Port& port, Nanos now) {
  const std::size_t index = static_cast<std::size_t>(&port - ports_.data());
  auto switch_baud = [&] {
    settings_.baud[index] = *port.pending_baud;
    port.pacer.reconfigure(*port.pending_baud, uls_hundredths_of_bits, port.pending_at);
    port.pending_baud.reset();
  };
  if (port.pending_baud && port.pending_port != index && port.pending_at < now) {
    // BR for the other port: it switches once the $OK has left the port the command came
    // on, even while it streams; what it still has queued goes on at the new speed (U36).
    take_until(port, port.pending_at);
    switch_baud();
  }
  take_until(port, now);
  while (port.outbox.size() > 65536) port.outbox.pop_front();  // nobody reads this port
  if (port.pending_baud && port.pending_at < now && port.pacer.queued() == 0) {
    // Strictly after: the runtime hands the $OK's last byte to the host at the old speed first.
    // BR takes effect once the $OK has left the line (§8 Set/Get Baud Rate, U36).
    switch_baud();
  }
}

void Firmware::take_line_output(std::size_t port, Nanos now, std::vector<LineByte>& out) {
  if (port >= ports_.size()) return;
  advance(now);
  auto& p = ports_[port];
  while (!p.outbox.empty() && p.outbox.front().done <= now) {
    out.push_back(p.outbox.front());
    p.outbox.pop_front();
  }
}

void Firmware::receive(std::size_t port, std::uint8_t byte, Nanos now) {
  if (port >= ports_.size()) return;
  advance(now);
  if (ports_[port].overrun && continue_overrun(port, byte, now)) return;
  auto& input = ports_[port].input;
  input.push_back(byte);
  while (!input.empty()) {
    const FrameScan scan = scan_frame(Bytes(input.data(), input.size()));
    if (scan.status == FrameStatus::need_more) break;
    if (scan.status == FrameStatus::invalid && scan.consumed == max_frame_length &&
        input.size() == max_frame_length + 1 && input.back() != '$' && input.back() != '#') {
      // 64 valid frame bytes and a 65th that neither ends the frame nor starts a new one:
      // the receive buffer overran (F5, U78). The rest of the line is lost up to its CR.
      ports_[port].overrun = std::array<std::uint8_t, 2>{input[0], input[1]};
      input.clear();
      break;
    }
    if (scan.status == FrameStatus::complete) {
      const std::vector<std::uint8_t> frame(scan.frame.begin(), scan.frame.end());
      input.erase(input.begin(), input.begin() + static_cast<std::ptrdiff_t>(scan.consumed));
      auto parsed = parse_frame(Bytes(frame.data(), frame.size()));
      if (parsed) {
        handle_frame(port, *parsed, now);
      } else if (!frame.empty() && frame[0] == '$') {
        reply(port, false, encode_error_reply(Address::none(), 1), now);  // malformed '$' frame (U37)
      } else if (frame.size() > 1 && frame[0] == '#' && settings_.address != 0 && frame[1] == settings_.address) {
        reply(port, false, encode_error_reply(Address::unit(settings_.address), 1), now);
      }
      continue;
    }
    // Invalid bytes (noise, a cut frame): dropped silently (U37).
    input.erase(input.begin(), input.begin() + static_cast<std::ptrdiff_t>(std::max<std::size_t>(scan.consumed, 1)));
  }
}

bool Firmware::continue_overrun(std::size_t port, std::uint8_t byte, Nanos now) {
  auto& overrun = ports_[port].overrun;
  if (byte == '$' || byte == '#') {
    overrun.reset();  // a new frame cuts the line short (F3): no answer
    return false;
  }
  if (byte == '\r') {
    const auto [start, address] = *overrun;
    overrun.reset();
    // Answered like a refused frame (U37): '$' by every unit, '#' by the addressed one only.
    if (start == '$') {
      reply(port, false, encode_error_reply(Address::none(), error_number::rx_buffer_overrun), now);
    } else if (settings_.address != 0 && address == settings_.address) {
      reply(port, false, encode_error_reply(Address::unit(settings_.address), error_number::rx_buffer_overrun), now);
    }
    return true;
  }
  if (byte < 0x20 || byte >= 0x7F) overrun.reset();  // not frame text: the line was noise (F4), no answer
  return true;
}

void Firmware::reply(std::size_t port, bool silent, const Result<FrameText>& frame, Nanos now) {
  if (silent || !frame) return;
  ports_[port].pacer.send(frame->bytes(), now);
}

void Firmware::reply_values(std::size_t port, Address to, bool silent, std::string_view mnemonic,
                            std::initializer_list<std::string_view> values, Nanos now) {
  const std::vector<std::string_view> list(values);
  reply(port, silent, encode_value_reply(to, mnemonic, list), now);
}

void Firmware::handle_frame(std::size_t port, const FrameView& frame, Nanos now) {
  Address to = Address::none();
  bool silent = false;
  if (frame.address.addressed) {
    if (frame.address.is_broadcast()) {
      silent = true;  // U4: every unit acts, none replies
      to = Address::unit(settings_.address);
    } else {
      if (settings_.address == 0 || frame.address.byte != settings_.address) return;  // U3
      to = Address::unit(settings_.address);
    }
  }
  if (frame.kind == FrameKind::time_between_events) {
    reply(port, silent, encode_error_reply(to, 1), now);
    return;
  }
  const CommandInfo* command = find_command(frame.mnemonic);
  if (command == nullptr) {
    reply(port, silent, encode_error_reply(to, 1), now);
    return;
  }
  const FormResult form = request_form(*command, frame.field_count);
  Verdict verdict = form.verdict;
  if (verdict.ok()) verdict = validate_request(*command, frame.fields(), settings_.units);
  if (verdict.ok()) verdict = check_while_measuring(*command, form.form, measuring_);
  if (!verdict.ok()) {
    reply(port, silent, encode_error_reply(to, verdict.error), now);
    return;
  }
  execute(port, to, silent, *command, form.form, frame, now);
}

void Firmware::execute(std::size_t port, Address to, bool silent, const CommandInfo& command, RequestForm form,
                       const FrameView& frame, Nanos now) {
  const std::string_view m = command.mnemonic;
  const auto fields = frame.fields();
  const bool get = form == RequestForm::get;
  const Units units = settings_.units;
  auto ok = [&] { reply(port, silent, encode_ok(to), now); };
  auto error = [&](int number) { reply(port, silent, encode_error_reply(to, number), now); };
  auto value = [&](std::string_view text) { reply_values(port, to, silent, m, {text}, now); };
  auto flag = [&](bool& field) {
    if (get) {
      value(field ? "1" : "0");
    } else {
      field = fields[0] == "1";
      ok();
    }
  };
  auto distance = [&](double& field) {
    if (get) {
      value(distance_text(field, units));
    } else {
      field = distance_to_metres(parse_number(fields[0]), units, command.min, command.max);  // U76
      ok();
    }
  };
  auto unsigned_value = [&](std::uint32_t& field) {
    if (get) {
      value(std::to_string(field));
    } else {
      field = parse_unsigned(fields[0]);
      ok();
    }
  };

  switch (command.id) {
    case CommandId::start:
      start_measuring(now);
      ok();
      break;
    case CommandId::stop:
      if (!measuring_) return error(86);  // Instrument Not Measuring (§10, U43)
      stop_measuring();
      ok();
      break;
    case CommandId::save:
      if (store_.save(settings_.to_json())) {
        ok();
      } else {
        error(10);  // "☒ must be resolved by LTI": memory failure
      }
      break;
    case CommandId::version:
      reply_values(port, to, silent, m, {"ULS emulator rangekit 1.0 protocol 0.97", "2026-11-25"}, now);
      break;
    case CommandId::status:
      value(std::to_string(wire_value(status_for(measuring_, settings_.mode))));
      break;
    case CommandId::measure:
      if (silent) {
        if (!measuring_) start_measuring(now);
        return;
      }
      if (settings_.mode == Mode::look_down) {
        // §8 Get Measurement: "Varies with measurement mode". Look down has a state at every
        // moment (the trip line), so a poll is answered at once with it, never queued (U70-U72).
        if (!measuring_) start_measuring(now);  // §2 ULS Autostart
        reply(port, false, encode_measurement(to, look_down_state()), now);
        return;
      }
      if (!measuring_) {
        start_measuring(now);  // §2 ULS Autostart: Get Measurement starts the unit
        polls_.push_back({port, to});
        return;
      }
      if (latest_.empty()) {
        polls_.push_back({port, to});
        return;
      }
      for (const auto& reading : latest_) reply(port, false, encode_measurement(to, reading), now);
      break;
    case CommandId::pointer:
      pointer_ = fields[0] == "1";
      ok();
      break;
    case CommandId::autostart:
      flag(settings_.autostart);
      break;
    case CommandId::pointer_autostart:
      flag(settings_.pointer_autostart);
      break;
    case CommandId::current_loop:
      flag(settings_.current_loop);
      break;
    case CommandId::continuous:
      flag(settings_.continuous);
      break;
    case CommandId::cooperative_filter:
      flag(settings_.cooperative_filter);
      break;
    case CommandId::dither:
      flag(settings_.dither);
      break;
    case CommandId::termination:
      flag(settings_.termination);
      break;
    case CommandId::time_between_events:
      flag(settings_.time_between_events);
      break;
    case CommandId::averaging_weight: {
      if (get) {
        value(std::to_string(settings_.averaging_weight));
        return;
      }
      const std::uint32_t weight = parse_unsigned(fields[0]);
      if (auto v = check_ppm_against_weight(settings_.ppm[0], weight); !v.ok()) return error(v.error);
      settings_.averaging_weight = weight;
      ok();
      break;
    }
    case CommandId::ppm: {
      if (get) {
        reply_values(port, to, silent, m, {std::to_string(settings_.ppm[0]), std::to_string(settings_.ppm[1])}, now);
        return;
      }
      // §2 "Pulses/Measure ... not available in the Look Down Mode": one value names no PPM there (U79).
      if (fields.size() == 1 && settings_.mode == Mode::look_down) return error(error_number::invalid_for_mode);
      auto ppm = settings_.ppm;
      if (fields.size() == 2) {
        ppm = {parse_unsigned(fields[0]), parse_unsigned(fields[1])};
      } else {
        ppm[settings_.mode == Mode::binning ? 1 : 0] = parse_unsigned(fields[0]);
      }
      if (auto v = check_ppm_against_weight(ppm[0], settings_.averaging_weight); !v.ok()) return error(v.error);
      settings_.ppm = ppm;
      ok();
      break;
    }
    case CommandId::prf:
      if (get) {
        reply_values(
            port, to, silent, m,
            {std::to_string(settings_.prf[0]), std::to_string(settings_.prf[1]), std::to_string(settings_.prf[2])},
            now);
        return;
      }
      if (fields.size() == 3) {
        for (std::size_t i = 0; i < 3; ++i) settings_.prf[i] = parse_unsigned(fields[i]);
      } else {
        settings_.prf[static_cast<std::size_t>(wire_value(settings_.mode) - 1)] = parse_unsigned(fields[0]);
      }
      ok();
      break;
    case CommandId::baud: {
      const std::size_t which = fields[0] == "1" ? 1 : 0;
      if (get) {
        reply_values(port, to, silent, m, {fields[0], std::to_string(settings_.baud[which])}, now);
        return;
      }
      ok();
      auto& target = ports_[which];
      target.pending_baud = parse_unsigned(fields[1]);
      target.pending_at = std::max(now, ports_[port].pacer.idle_at(now));
      target.pending_port = port;
      break;
    }
    case CommandId::bin_size:
      if (get) {
        value(std::to_string(settings_.bin_size));
        return;
      }
      settings_.bin_size = static_cast<std::uint8_t>(parse_unsigned(fields[0]));
      ok();
      break;
    case CommandId::bin_threshold:
      unsigned_value(settings_.bin_hits);
      break;
    case CommandId::display:
      if (get) return value(std::to_string(wire_value(settings_.display)));
      settings_.display = to_display_mode(parse_unsigned(fields[0])).value_or(settings_.display);
      ok();
      break;
    case CommandId::mode:
      if (get) return value(std::to_string(wire_value(settings_.mode)));
      settings_.mode = to_mode(parse_unsigned(fields[0])).value_or(settings_.mode);
      ok();
      break;
    case CommandId::output_port:
      if (get) return value(std::to_string(wire_value(settings_.output_port)));
      settings_.output_port = to_output_port(parse_unsigned(fields[0])).value_or(settings_.output_port);
      ok();
      break;
    case CommandId::units:
      if (get) return value(std::to_string(wire_value(settings_.units)));
      settings_.units = to_units(parse_unsigned(fields[0])).value_or(settings_.units);
      ok();
      break;
    case CommandId::power:
      if (get) return value(std::to_string(wire_value(settings_.power)));
      settings_.power = to_power_level(parse_unsigned(fields[0])).value_or(settings_.power);
      ok();
      break;
    case CommandId::fault_current:
      if (get) return value(number_text(settings_.fault_current_ma));
      settings_.fault_current_ma = parse_number(fields[0]);
      ok();
      break;
    case CommandId::fault_timeout:
      if (get) return value(number_text(settings_.fault_timeout_s));
      settings_.fault_timeout_s = parse_number(fields[0]);
      ok();
      break;
    case CommandId::range_at_20ma:
    case CommandId::range_at_4ma: {
      double& field = command.id == CommandId::range_at_20ma ? settings_.range_at_20ma_m : settings_.range_at_4ma_m;
      if (get) return value(distance_text(field, units));
      const double metres = distance_to_metres(parse_number(fields[0]), units, command.min, command.max);  // U76
      const double low = command.id == CommandId::range_at_4ma ? metres : settings_.range_at_4ma_m;
      const double high = command.id == CommandId::range_at_20ma ? metres : settings_.range_at_20ma_m;
      if (auto v = check_current_loop_range(low, high); !v.ok()) return error(v.error);
      field = metres;
      ok();
      break;
    }
    case CommandId::long_gate:
      distance(settings_.long_gate_m);
      break;
    case CommandId::short_gate:
      distance(settings_.short_gate_m);
      break;
    case CommandId::trip_point:
      distance(settings_.trip_point_m);
      break;
    case CommandId::offset:
      distance(settings_.offset_m);
      break;
    case CommandId::trip_timeout:
      if (get) return value(to_hex_text(settings_.trip_timeout_pulses).view());
      settings_.trip_timeout_pulses = parse_trip_timeout(fields[0]).value_or(settings_.trip_timeout_pulses);
      ok();
      break;
    case CommandId::address:
      if (get) {
        if (settings_.address == 0) return error(82);  // U3
        return value(std::to_string(unit_address_value(settings_.address)));
      }
      ok();  // the reply still carries the old address
      settings_.address = static_cast<std::uint8_t>(fields[0][0]);
      break;
  }
}

// --- Measuring ---

std::uint32_t Firmware::current_prf() const noexcept {
  return settings_.prf[static_cast<std::size_t>(wire_value(settings_.mode) - 1)];
}

std::uint32_t Firmware::current_ppm() const noexcept {
  return settings_.mode == Mode::binning ? settings_.ppm[1] : settings_.ppm[0];
}

Nanos Firmware::pulse_time(std::uint64_t index) const noexcept {
  // From a pulse counter, never by adding rounded periods: no drift over long runs.
  const std::uint64_t whole = index / run_prf_;
  const std::uint64_t part = index % run_prf_;
  return run_start_ + Nanos(static_cast<std::int64_t>(whole * 1'000'000'000ULL + part * 1'000'000'000ULL / run_prf_));
}

void Firmware::reset_cycle() {
  cycle_pulses_ = 0;
  any_return_ = false;
  returns_m_.clear();
  returns_width_ps_.clear();
  bins_.fill(0);
  max_bin_ = 0;
  bin_targets_ = 0;
}

void Firmware::start_measuring(Nanos now) {
  measuring_ = true;
  run_start_ = now;
  run_prf_ = current_prf();
  next_pulse_ = 1;  // the first pulse fires one period after the start
  reset_cycle();
  latest_.clear();
  reference_m_.reset();
  reference_pulses_ = 0;
  reference_candidate_m_ = 0;
  present_ = false;
  presence_tbe_ = TimeBetweenEvents{};
  disagreeing_ = 0;
  have_no_presence_edge_ = false;
  stable_pulses_ = 0;
  longer_pulses_ = 0;
  error_since_.reset();
  last_distance_m_.reset();  // the loop holds only a distance of this run (U81)
}

void Firmware::stop_measuring() {
  measuring_ = false;
  polls_.clear();
}

void Firmware::advance(Nanos now) {
  if (now < last_now_) now = last_now_;
  last_now_ = now;
  while (measuring_) {
    const Nanos t = pulse_time(next_pulse_);
    if (t > now) break;
    fire_pulse(t);
    ++next_pulse_;
  }
  for (auto& port : ports_) drain(port, now);
}

Nanos Firmware::next_deadline() const { return earliest_event(false); }

Nanos Firmware::next_wake() const { return earliest_event(true); }

Nanos Firmware::earliest_event(bool whole_runs) const {
  Nanos earliest = Nanos::max();
  for (const auto& port : ports_) {
    const Nanos output =
        whole_runs && port.pacer.queued() > 0 ? port.pacer.idle_at(last_now_) : port.pacer.next_completion();
    earliest = std::min(earliest, output);
    if (port.pending_baud) {
      const bool other_port = port.pending_port != static_cast<std::size_t>(&port - ports_.data());
      const Nanos idle = other_port ? port.pending_at : port.pacer.idle_at(last_now_);
      earliest = std::min(earliest, std::max({port.pending_at, idle, last_now_}) + Nanos(1));
    }
  }
  if (measuring_) {
    if (settings_.mode == Mode::look_down) {
      earliest = std::min(earliest, pulse_time(next_pulse_));
    } else {
      const std::uint32_t ppm = current_ppm();
      std::uint64_t remaining = ppm > cycle_pulses_ ? ppm - cycle_pulses_ - 1 : 0;
      if (settings_.mode == Mode::binning) remaining = std::min(remaining, pulses_before_restart() - 1);
      earliest = std::min(earliest, pulse_time(next_pulse_ + remaining));
    }
  }
  return earliest;
}

double Firmware::modelled_width_ps(double strength) {
  // The log is the costliest step of a pulse; a fixed target gives the same strength
  // every pulse, so the last answer is kept.
  if (strength != width_cache_strength_) {
    width_cache_strength_ = strength;
    width_cache_ps_ = (weakest_width_ns + width_ns_per_doubling * std::log2(1.0 + strength)) * 1000.0;
  }
  return width_cache_ps_;
}

std::uint64_t Firmware::pulses_before_restart() const noexcept {
  // A pulse adds at most one hit per target, one per (rounded-up) noise hit and one of
  // dust, so the 15th target of U42 cannot appear sooner than this many pulses from now.
  const auto per_pulse = static_cast<std::uint64_t>(scene_.targets.size()) +
                         static_cast<std::uint64_t>(std::ceil(scene_.ambient_noise)) + 1;
  auto pulses_for = [per_pulse](std::uint64_t hits) {
    return std::max<std::uint64_t>(1, (hits + per_pulse - 1) / per_pulse);
  };
  std::uint64_t pulses = pulses_for(restart_targets - std::min(bin_targets_, restart_targets));
  if (max_bin_ < settings_.bin_hits) pulses = std::max(pulses, pulses_for(settings_.bin_hits - max_bin_));
  return pulses;
}

double Firmware::max_range_m(double reflectivity, bool cooperative) const noexcept {
  const auto level = static_cast<std::size_t>(wire_value(settings_.power));
  if (cooperative) return cooperative_range_m;  // §9: 1700 m in all three power columns (U75)
  // §9 ranges at 90% and 20%, linear in reflectivity between and beyond them.
  const double r = std::clamp(reflectivity, 0.0, 1.0);
  const double range = gray_range_m[level] + (white_range_m[level] - gray_range_m[level]) * (r - 0.2) / 0.7;
  return std::max(range, 1.0);
}

std::optional<Firmware::PulseReturn> Firmware::first_return(Nanos t, bool certain, double min_width_ps) {
  if (fault_no_return_) return std::nullopt;
  std::optional<PulseReturn> best;
  for (const auto& target : scene_.targets) {
    const double d = target.motion.position_at(t);
    if (!passes_gates(settings_, d, target.cooperative)) continue;
    const double range = max_range_m(target.reflectivity, target.cooperative);
    if (d > range) continue;  // below the detection threshold
    if (best && best->distance_m <= d) continue;
    if (!certain && random_() >= detect_threshold) continue;
    const double ratio = range / d;
    const double strength = ratio * ratio;
    const double width_ps = target.pulse_width_ns ? *target.pulse_width_ns * 1000.0 : modelled_width_ps(strength);
    if (width_ps < min_width_ps) continue;  // too narrow: rejected like noise (§2 Min. Pulse Width, U41)
    best = PulseReturn{d, strength, target.cooperative, width_ps};
  }
  return best;
}

void Firmware::fire_pulse(Nanos t) {
  switch (settings_.mode) {
    case Mode::averaging:
      fire_averaging(t);
      break;
    case Mode::binning:
      fire_binning(t);
      break;
    case Mode::look_down:
      fire_look_down(t);
      break;
  }
}

void Firmware::fire_averaging(Nanos t) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double min_width_ps = settings_.min_pulse_width_ns * 1000.0;
  // Dust near the unit answers first; a minimum pulse width above its width rejects it (U41).
  const bool dust = scene_.dust > 0 && uniform(random_) < scene_.dust && dust_width_ns * 1000.0 >= min_width_ps;
  if (dust) {
    any_return_ = true;  // a weak return the noise filter rejects: a bad pulse
  } else if (auto hit = first_return(t, false, min_width_ps)) {
    any_return_ = true;
    const double sigma = hit->cooperative ? cooperative_jitter_m : jitter_m;
    double raw = hit->distance_m + sigma * normal_(random_);
    // The pulse is timed in quanta; dithering shifts the quantum grid over a 32-pulse cycle.
    const double shift = settings_.dither
                             ? (static_cast<double>(returns_m_.size() % dither_cycle) + 0.5) / dither_cycle * quantum_m
                             : 0.0;
    raw = std::round((raw + shift) / quantum_m) * quantum_m - shift;
    returns_m_.push_back(raw);
    returns_width_ps_.push_back(hit->width_ps);
  }
  if (++cycle_pulses_ >= settings_.ppm[0]) complete_averaging(t);
}

double Firmware::noise_filter_centre(double& window) {
  // "Averaging with Noise Filtering" (§8 MM 1, U48): the median return is the target;
  // returns farther from it than max(0.5 m, 6 x the median absolute deviation) are noise
  // (a missed near target answered by one behind it). A moving target spreads its returns
  // evenly, so the window grows with its travel and none of them is dropped.
  scratch_.assign(returns_m_.begin(), returns_m_.end());
  const auto middle = scratch_.begin() + static_cast<std::ptrdiff_t>(scratch_.size() / 2);
  std::nth_element(scratch_.begin(), middle, scratch_.end());
  const double centre = *middle;
  for (auto& value : scratch_) value = std::abs(value - centre);
  std::nth_element(scratch_.begin(), middle, scratch_.end());
  window = std::max(noise_window_m, 6.0 * *middle);
  return centre;
}

void Firmware::complete_averaging(Nanos t) {
  ++measurements_;
  double sum_m = 0;
  double width_sum_ps = 0;
  std::uint32_t good = 0;
  if (!returns_m_.empty()) {
    double window = 0;
    const double centre = noise_filter_centre(window);
    for (std::size_t i = 0; i < returns_m_.size() && good < settings_.averaging_weight; ++i) {
      if (std::abs(returns_m_[i] - centre) > window) continue;
      sum_m += returns_m_[i];
      width_sum_ps += returns_width_ps_[i];
      ++good;
    }
  }
  if (!any_return_) {
    record_error(4, t);
    emit({MeasurementError{4}}, t);
  } else if (good < settings_.averaging_weight) {
    record_error(5, t);
    emit({MeasurementError{5}}, t);
  } else {
    const double metres = sum_m / good + settings_.offset_m;
    record_distance(metres, t);
    AveragingReading reading;
    const auto width = static_cast<std::uint32_t>(std::clamp(std::round(width_sum_ps / good), 0.0, 9'999'999.0));
    if (settings_.display != DisplayMode::intensity) {
      const double user = from_metres(metres, settings_.units);
      reading.range =
          make_range(settings_.units == Units::metres ? std::round(user * 1000) / 1000 : std::round(user * 100) / 100,
                     settings_.units);
    }
    if (settings_.display != DisplayMode::range) reading.pulse_width_ps = width;
    emit({reading}, t);
  }
  reset_cycle();
}

void Firmware::fire_binning(Nanos t) {
  const BinSize size = to_bin_size(settings_.bin_size).value_or(BinSize::inch_1);
  const double bin_m = bin_size_m(size);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  bool crossed = false;
  auto hit_at = [&](double d) {
    if (d < 0) return;
    const auto index = static_cast<std::size_t>(d / bin_m);
    if (index >= bins_.size()) return;
    const std::uint32_t hits = ++bins_[index];
    max_bin_ = std::max(max_bin_, hits);
    crossed = crossed || hits == settings_.bin_hits;
  };
  if (!fault_no_return_) {
    for (const auto& target : scene_.targets) {
      const double d = target.motion.position_at(t);
      if (!passes_gates(settings_, d, target.cooperative)) continue;
      // No threshold in binning (§3): weak returns still land, with a probability
      // falling with the signal strength (range / distance)^2.
      const double ratio = max_range_m(target.reflectivity, target.cooperative) / d;
      const double p = std::min(detect_probability, 0.5 * ratio * ratio);
      if (uniform(random_) >= p) continue;
      std::normal_distribution<double> noise(0.0, target.cooperative ? cooperative_jitter_m : jitter_m);
      hit_at(d + noise(random_));
    }
    const double span = bin_m * static_cast<double>(bins_.size());
    double noise_hits = scene_.ambient_noise;
    while (noise_hits > 0) {
      if (noise_hits >= 1 || uniform(random_) < noise_hits) hit_at(uniform(random_) * span);
      noise_hits -= 1;
    }
    if (scene_.dust > 0 && uniform(random_) < scene_.dust) hit_at(minimum_range_m + uniform(random_) * 30.0);
  }
  ++cycle_pulses_;
  if (crossed) {
    // §3: "If 15 targets appear during binning, the unit restarts the firing sequence and
    // will not find targets beyond the last one detected" (U42): the burst ends here.
    bin_targets_ = count_bin_targets();
    if (bin_targets_ >= restart_targets) {
      ++restarts_;
      complete_binning(t);
      return;
    }
  }
  if (cycle_pulses_ >= settings_.ppm[1]) complete_binning(t);
}

std::size_t Firmware::count_bin_targets() const noexcept {
  std::size_t runs = 0;
  bool in_run = false;
  for (const auto hits : bins_) {
    const bool over = hits >= settings_.bin_hits;
    if (over && !in_run) ++runs;
    in_run = over;
  }
  return runs;
}

void Firmware::complete_binning(Nanos t) {
  ++measurements_;
  const BinSize size = to_bin_size(settings_.bin_size).value_or(BinSize::inch_1);
  const double bin_m = bin_size_m(size);
  struct Found {
    std::size_t bin;
    std::uint32_t hits;
  };
  std::vector<Found> found;
  for (std::size_t i = 0; i < bins_.size() && found.size() < max_binning_targets; ++i) {
    if (bins_[i] < settings_.bin_hits) continue;
    // A run of neighbouring bins over the threshold is one target, at its strongest bin (U38).
    Found best{i, bins_[i]};
    while (i + 1 < bins_.size() && bins_[i + 1] >= settings_.bin_hits) {
      ++i;
      if (bins_[i] > best.hits) best = {i, bins_[i]};
    }
    found.push_back(best);  // 15 targets: the unit restarts and sees nothing beyond (§3)
  }
  if (found.empty()) {
    record_error(4, t);
    emit({MeasurementError{4}}, t);
  } else {
    std::vector<Reading> lines;
    for (std::size_t i = 0; i < found.size(); ++i) {
      const double metres = (static_cast<double>(found[i].bin) + 0.5) * bin_m + settings_.offset_m;
      if (i == 0) record_distance(metres, t);
      const double user = from_metres(metres, settings_.units);
      BinningTarget target;
      target.index = static_cast<std::uint8_t>(i);
      target.count = static_cast<std::uint8_t>(found.size());
      target.range =
          make_range(settings_.units == Units::metres ? std::round(user * 1000) / 1000 : std::round(user * 100) / 100,
                     settings_.units);
      target.strength = std::min<std::uint32_t>(found[i].hits, 65535);
      lines.emplace_back(target);
    }
    emit(lines, t);
  }
  reset_cycle();
}

void Firmware::fire_look_down(Nanos t) {
  const std::uint64_t pulse = next_pulse_;
  // Look down fires without averaging: a target within range always answers (U38).
  const auto hit = first_return(t, true);
  const std::optional<double> d = hit ? std::optional<double>(hit->distance_m) : std::nullopt;
  if (!reference_m_) {
    // Reference on start (§3): the longest distance over the first 30 pulses.
    if (d) reference_candidate_m_ = std::max(reference_candidate_m_, *d);
    if (++reference_pulses_ >= look_down_decision_pulses && reference_candidate_m_ > 0) {
      reference_m_ = reference_candidate_m_;
      have_no_presence_edge_ = true;
      no_presence_edge_pulse_ = pulse;
    }
    return;
  }
  const bool presence_pulse = d && *d < *reference_m_ - settings_.trip_point_m;
  if (presence_pulse != present_) {
    // 30 consecutive pulses decide a change (§3, U34).
    if (++disagreeing_ >= look_down_decision_pulses) change_presence(presence_pulse, pulse, t);
  } else {
    disagreeing_ = 0;
  }
  if (present_ && d) {
    // Re-reference on a distance that stays put for TT pulses while tripped (§3). The trip is
    // released like any end of presence: `$BM,0`, or with TB on `$0` starting the no-presence
    // time the next `$XXXX` counts (U73).
    if (std::abs(*d - stable_m_) > std::max(settings_.trip_point_m / 2, 0.1)) {
      stable_m_ = *d;
      stable_pulses_ = 0;
    } else if (++stable_pulses_ >= settings_.trip_timeout_pulses) {
      reference_m_ = *d;
      change_presence(false, pulse, t);
    }
  }
  if (!present_ && d && *d > *reference_m_ + settings_.trip_point_m / 2) {
    // A longer distance while not tripped becomes the reference after about 2 s (§3).
    longer_m_ = longer_pulses_ == 0 ? *d : std::max(longer_m_, *d);
    if (++longer_pulses_ >= 2ULL * run_prf_) {
      reference_m_ = longer_m_;
      longer_pulses_ = 0;
    }
  } else {
    longer_pulses_ = 0;
  }
}

void Firmware::change_presence(bool present, std::uint64_t pulse, Nanos t) {
  present_ = present;
  disagreeing_ = 0;
  stable_pulses_ = 0;
  if (present) {
    // §3: "the number of fire pulses between not present and present events" (U12).
    presence_tbe_ = have_no_presence_edge_ ? tbe_from_pulses(pulse - no_presence_edge_pulse_)
                                           : TimeBetweenEvents{TimeBetweenEvents::Kind::overflow, 0};
  } else {
    no_presence_edge_pulse_ = pulse;
    have_no_presence_edge_ = true;
  }
  emit({look_down_state()}, t);
}

Reading Firmware::look_down_state() const noexcept {
  // Before the first detection the trip line is low (§3), so OFF / `$0` (U71). With TB on a
  // presence is told by its `$XXXX`, the line sent at its start (§8, U72).
  if (!settings_.time_between_events) return LookDownReading{present_};
  return present_ ? presence_tbe_ : TimeBetweenEvents{};
}

Address Firmware::measurement_address() const noexcept {
  if (settings_.address != 0 && settings_.output_port == OutputPort::universal_rs485 &&
      measurement_port() == universal_port)
    return Address::unit(settings_.address);
  return Address::none();
}

std::size_t Firmware::measurement_port() const noexcept {
  // §3 "Time between events can be logged using the configuration port only", whatever MO
  // says: more specific than §4's look-down "configuration port ... system setup only" (U74).
  if (settings_.mode == Mode::look_down && settings_.time_between_events) return configuration_port;
  return settings_.output_port == OutputPort::configuration ? configuration_port : universal_port;
}

void Firmware::emit(const std::vector<Reading>& readings, Nanos t) {
  latest_ = readings;
  for (const auto& poll : polls_) {
    for (const auto& reading : readings) reply(poll.port, false, encode_measurement(poll.to, reading), t);
  }
  polls_.clear();
  if (!settings_.continuous) return;
  auto& port = ports_[measurement_port()];
  drain(port, t);  // bytes already on the wire by t leave the UART first
  // One measurement may wait behind the one on the wire (U39); a measurement completing
  // while one already waits is skipped, so the §9 serial limits emerge from the pacing.
  if (port.last_line_start > t) {
    ++skipped_;
    return;
  }
  port.last_line_start = port.pacer.idle_at(t);
  const Address from = measurement_address();
  for (const auto& reading : readings) {
    if (auto line = encode_measurement(from, reading)) port.pacer.send(line->bytes(), t);
  }
}

void Firmware::record_error(int number, Nanos t) {
  last_error_ = number;
  if (!error_since_) error_since_ = t;
}

void Firmware::record_distance(double metres, Nanos) {
  last_distance_m_ = metres;
  last_error_ = 0;
  error_since_.reset();
}

// --- Outputs and control ---

Outputs Firmware::outputs(Nanos now) const {
  Outputs out;
  out.measuring = measuring_;
  out.laser_firing = measuring_;
  out.pointer = pointer_;
  out.trip = measuring_ && settings_.mode == Mode::look_down && present_;
  out.status = wire_value(status_for(measuring_, settings_.mode));
  out.measurements = measurements_;
  out.skipped_lines = skipped_;
  out.binning_restarts = restarts_;
  out.last_distance_m = last_distance_m_;
  out.last_error = last_error_;
  if (settings_.current_loop && measuring_) {
    // §6, §8 AT "timeout allowed before 4-20mA goes to the fault current indication": fault
    // current after AT seconds of errors 4/5, also before the run's first distance (U81); until
    // then the last distance of the run is held, 4 mA when there is none yet.
    const bool fault = error_since_ && seconds(now - *error_since_) >= settings_.fault_timeout_s;
    if (fault) {
      out.current_ma = settings_.fault_current_ma;
    } else if (last_distance_m_) {
      out.current_ma = loop_current_ma(*last_distance_m_, settings_.range_at_4ma_m, settings_.range_at_20ma_m)
                           .value_or(settings_.fault_current_ma);
    } else {
      out.current_ma = loop_min_ma;
    }
  }
  return out;
}

void Firmware::set_scene(Scene scene, Nanos now) {
  advance(now);
  scene_ = std::move(scene);
}

bool Firmware::move_target(std::size_t index, double distance_m, Nanos now) {
  advance(now);
  if (index >= scene_.targets.size()) return false;
  scene_.targets[index].motion = Motion::fixed(distance_m);
  return true;
}

void Firmware::set_no_return_fault(bool on, Nanos now) {
  advance(now);
  fault_no_return_ = on;
}

bool Firmware::set_min_pulse_width(double nanoseconds, Nanos now) {
  advance(now);
  if (!(nanoseconds >= 0.0 && nanoseconds <= max_min_pulse_width_ns)) return false;
  settings_.min_pulse_width_ns = nanoseconds;
  return true;
}

nlohmann::json Firmware::control(const nlohmann::json& request, Nanos now) {
  const std::string command = request.value("cmd", "");
  if (command == "outputs") {
    advance(now);
    const Outputs o = outputs(now);
    nlohmann::json reply{{"ok", true},
                         {"device", label()},
                         {"current_ma", o.current_ma},
                         {"trip", o.trip},
                         {"laser_firing", o.laser_firing},
                         {"pointer", o.pointer},
                         {"status", o.status},
                         {"measuring", o.measuring},
                         {"measurements", o.measurements},
                         {"skipped_lines", o.skipped_lines},
                         {"binning_restarts", o.binning_restarts},
                         {"min_pulse_width_ns", settings_.min_pulse_width_ns},
                         // What $PF holds, per mode (averaging, binning, look down), so a test can
                         // check a write from outside the link (the dashboard's PRF test).
                         {"prf_hz", {settings_.prf[0], settings_.prf[1], settings_.prf[2]}},
                         // What $TT holds, in pulses (§8 "seconds * 3000"): the page's Short Timeout
                         // (§3 "8,000 laser pulses") checked from outside the link.
                         {"trip_timeout_pulses", settings_.trip_timeout_pulses},
                         {"last_error", o.last_error}};
    reply["distance_m"] = o.last_distance_m ? nlohmann::json(*o.last_distance_m) : nlohmann::json(nullptr);
    return reply;
  }
  if (command == "set_scene") {
    if (!request.contains("scene")) return {{"error", "set_scene: needs 'scene' (an object like the TOML file)"}};
    auto scene = scene_from_json(request.at("scene"));
    if (!scene) return {{"error", "set_scene: " + scene.error().message}};
    set_scene(std::move(*scene), now);
    return {{"ok", true}, {"device", label()}};
  }
  if (command == "move_target") {
    // The scene file's range (distance_m 0 .. 5000 m), so no value the file refuses gets in this way.
    const auto index = control_number(request, "target", 0.0, static_cast<double>(scene_.targets.size()), 0.0);
    if (!index || *index != std::floor(*index))
      return {{"error", "move_target: 'target' must be the index of one of the scene's " +
                            std::to_string(scene_.targets.size()) + " targets (0, 1, ...)"}};
    const auto distance = control_number(request, "distance_m", 0.0, max_scene_distance_m);
    if (!distance) return {{"error", distance.error().message}};
    if (!move_target(static_cast<std::size_t>(*index), *distance, now))
      return {{"error", "move_target: no target " + std::to_string(static_cast<std::size_t>(*index))}};
    return {{"ok", true}, {"device", label()}};
  }
  if (command == "fault") {
    const std::string kind = request.value("kind", "no_return");
    if (kind != "no_return") return {{"error", "fault: unknown kind '" + kind + "' (no_return)"}};
    set_no_return_fault(request.value("on", true), now);
    return {{"ok", true}, {"device", label()}};
  }
  if (command == "min_pulse_width") {
    if (!request.contains("ns") || !request.at("ns").is_number())
      return {{"error", "min_pulse_width: needs 'ns' (number)"}};
    if (!set_min_pulse_width(request.at("ns").get<double>(), now))
      return {{"error", "min_pulse_width: ER 87 Invalid Minimum Pulse Width (0 .. 9999.999 ns)"}};
    return {{"ok", true}, {"device", label()}};
  }
  if (command == "power_cycle") {
    power_cycle(now);
    return {{"ok", true}, {"device", label()}};
  }
  return {{"error", "unknown command '" + command +
                        "' (ULS: outputs, set_scene, move_target, fault, min_pulse_width, power_cycle)"}};
}

}  // namespace rangekit::uls::emulator
