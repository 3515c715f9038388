// The LS5 firmware model. Decisions: docs/conformance.md L25-L36,
// behaviour and scene format: docs/emulator-ls5.md.
#include "rangekit/ls5/emulator/firmware.hpp"

#include "rangekit/core/text.hpp"
#include "rangekit/sim/control_socket.hpp"

#include <algorithm>
#include <cmath>

namespace rangekit::ls5::emulator {

namespace {

using namespace std::chrono_literals;

constexpr Nanos init_time = 4s;            // §8.2 standby: initialisation
constexpr Nanos standby_listen = 5s;       // §8.2: 19200 8N1 waiting for commands
constexpr Nanos standby_settle = 500ms;    // §8.2: operating 0.5 s after the emitter lights up
constexpr double bright_exposure_us = 20;  // exposure a white target needs (scene reflectivity 1)

Nanos from_ms(double ms) { return Nanos(static_cast<std::int64_t>(std::llround(ms * 1e6))); }
double seconds_of(Nanos t) { return static_cast<double>(t.count()) / 1e9; }

rangekit::SerialSettings settings_from(std::uint32_t baud, const ByteFormat& format) {
  rangekit::SerialSettings settings;
  settings.baud = baud;
  settings.parity = format.parity == Parity::none   ? rangekit::Parity::none
                    : format.parity == Parity::even ? rangekit::Parity::even
                                                    : rangekit::Parity::odd;
  settings.stop_bits = format.stop_bits;
  return settings;
}

const rangekit::SerialSettings standby_settings{19200, rangekit::Parity::none, 1};

}  // namespace

Result<OrderingCode> parse_model(std::string_view text) {
  if (text.starts_with("LS5-")) return parse_ordering_code(text);
  const std::string message =
      "model '" + std::string(text) + "' is not LOWER_MM/RANGE_MM (e.g. 8.1234/40.001) or an ordering code (LS5-...)";
  const auto slash = text.find('/');
  if (slash == std::string_view::npos) return make_error(Errc::bad_number, message);
  try {
    std::size_t used1 = 0;
    std::size_t used2 = 0;
    const std::string lower(text.substr(0, slash));
    const std::string range(text.substr(slash + 1));
    OrderingCode code;
    code.lower_boundary_mm = std::stod(lower, &used1);
    code.range_mm = std::stod(range, &used2);
    if (used1 != lower.size() || used2 != range.size() || code.lower_boundary_mm < 0 || code.range_mm <= 0) {
      return make_error(Errc::bad_number, message);
    }
    code.interface = DigitalInterface::rs485_ethernet;  // the version decides (L6)
    return code;
  } catch (const std::exception&) {
    return make_error(Errc::bad_number, message);
  }
}

Firmware::Firmware(FirmwareConfig config)
    : config_(std::move(config)),
      store_(config_.state_dir,
             "ls5-" + std::to_string(config_.serial_number) + "-" + text::hex_byte(config_.factory_address)),
      random_(config_.seed + config_.factory_address),
      pacer_(115200, 1000) {}

Result<std::unique_ptr<Firmware>> Firmware::create(FirmwareConfig config, Nanos now) {
  const auto version = try_parse_firmware_version(config.version_text);
  if (!version) {
    return make_error(Errc::bad_number,
                      "version '" + config.version_text + "' is not LS5.<major>.<minor> (e.g. LS5.12.0)");
  }
  if (config.factory_address == broadcast_address) {
    return make_error(Errc::out_of_range, "address 00 is the broadcast address; a sensor has 01-FF");
  }
  auto identification =
      make_identification(config.version_text, config.lower_boundary_mm, config.range_mm, config.serial_number);
  if (!identification) return std::move(identification).error();
  if (auto field = encode_identification_field(*identification); !field) return std::move(field).error();
  const bool config_ethernet = config.ethernet.value_or(true);
  std::unique_ptr<Firmware> firmware(new Firmware(std::move(config)));
  firmware->version_ = *version;
  firmware->model_ = SensorModel{*version, version->at_least(firmware_12_x) && config_ethernet};
  auto stored = firmware->store_.load();
  if (!stored) return std::move(stored).error();
  if (*stored) {
    const auto& memory = **stored;
    if (!memory.contains("parameters") || !memory["parameters"].is_array() || memory["parameters"].size() != 256) {
      return make_error(Errc::invalid_frame, firmware->store_.file_path() + ": no 256-byte \"parameters\" array");
    }
    std::array<std::uint8_t, 256> rom{};
    for (std::size_t i = 0; i < 256; ++i) rom[i] = memory["parameters"][i].get<std::uint8_t>();
    firmware->rom_ = rom;
  }
  firmware->power_cycle(now);
  return firmware;
}

std::array<std::uint8_t, 256> Firmware::table_defaults() const {
  std::array<std::uint8_t, 256> memory{};
  for (const auto& parameter : parameter_table()) {
    memory[parameter.address] = default_byte(parameter, config_.serial_number);
  }
  return memory;
}

std::array<std::uint8_t, 256> Firmware::delivered_rom() const {
  auto memory = table_defaults();
  memory[address::network_address] = config_.factory_address;  // --address: set and stored before delivery (L55)
  return memory;
}

void Firmware::load_rom_into_ram() { ram_ = rom_ ? *rom_ : delivered_rom(); }

Status Firmware::save_rom() {
  if (!rom_) return ok_status();
  nlohmann::json memory;
  memory["parameters"] = nlohmann::json::array();
  for (const auto byte : *rom_) memory["parameters"].push_back(byte);
  auto saved = store_.save(memory);
  state_error_ = saved;
  return saved;
}

std::optional<std::uint8_t> Firmware::rom(std::uint8_t address) const {
  if (!rom_) return std::nullopt;
  return (*rom_)[address];
}

rangekit::SerialSettings Firmware::stored_serial_settings() const {
  const auto baud = baud_rate_from_code(ram_[address::baud_rate]).value_or(115200);
  const auto format = byte_format_from_code(ram_[address::byte_format]).value_or(ByteFormat{0, Parity::none, 1, "8N1"});
  return settings_from(baud, format);
}

std::uint32_t Firmware::bits_hundredths(const rangekit::SerialSettings& settings) const {
  return static_cast<std::uint32_t>(settings.bits_per_byte()) * 100U;
}

void Firmware::apply_serial(const rangekit::SerialSettings& settings, Nanos now) {
  drain_pacer(now);
  pacer_.reconfigure(settings.baud, bits_hundredths(settings), now);
  serial_ = settings;
}

rangekit::SerialSettings Firmware::port_settings(std::size_t) const { return serial_; }

std::string_view Firmware::phase_name() const noexcept {
  switch (phase_) {
    case Phase::initializing:
      return "initializing";
    case Phase::standby:
      return "standby";
    case Phase::operating:
      break;
  }
  return "operating";
}

void Firmware::power_cycle(Nanos now) {
  last_now_ = now;
  pacer_.clear();
  sent_.clear();
  rx_.clear();
  streaming_ = false;
  pending_serial_.reset();
  pending_serial_at_ = Nanos::max();
  previous_raw_.reset();
  last_valid_.reset();
  window_.clear();
  current_ = ResultCode{};
  latched_ = ResultCode{};
  last_result_code_.reset();
  measured_once_ = false;
  thinning_count_ = 0;
  udp_fill_ = 0;
  last_measurement_ = Nanos::min();
  load_rom_into_ram();
  on_ = ram_[address::power_on_state] == 0x01;
  analog_ = config_.analog.min;
  oc1_ = oc2_ = false;
  const auto stored = stored_serial_settings();
  if (version_.at_least(firmware_6_0) && stored.baud > 115200) {
    // §8.2 standby: 4 s initialisation (deaf), 5 s at 19200 8N1, then the stored settings.
    phase_ = Phase::initializing;
    phase_until_ = now + init_time;
    apply_serial(standby_settings, now);
    next_measurement_ = Nanos::max();
    return;
  }
  apply_serial(stored, now);
  phase_ = Phase::operating;
  phase_until_ = Nanos::max();
  update_outputs();
  next_measurement_ = on_ && ram_[address::triggering] == 0 ? now + period() : Nanos::max();
}

void Firmware::enter_operating(Nanos now) {
  phase_ = Phase::operating;
  phase_until_ = Nanos::max();
  // §8.2: "the sensor sets up according to the saved parameters": what standby wrote without FL is dropped (L54).
  load_rom_into_ram();
  apply_serial(stored_serial_settings(), now);
  on_ = ram_[address::power_on_state] == 0x01;
  update_outputs();
  next_measurement_ = on_ && ram_[address::triggering] == 0 ? now + standby_settle : Nanos::max();
}

std::uint16_t Firmware::u16(std::uint8_t low_address) const noexcept {
  return static_cast<std::uint16_t>(ram_[low_address] | (ram_[static_cast<std::uint8_t>(low_address + 1)] << 8));
}

Nanos Firmware::period() const noexcept {
  const std::uint16_t code = std::max<std::uint16_t>(1, u16(address::period_low));
  return Nanos(static_cast<std::int64_t>(code) * 100'000);  // 0.1 ms units
}

// The network address in decimal, as --address takes it and every host message prints it.
std::string Firmware::label() const { return "LS5 " + std::to_string(ram_[address::network_address]); }

// ---- Serial side ----

void Firmware::receive(std::size_t, std::uint8_t byte, Nanos now) {
  last_now_ = std::max(last_now_, now);
  if (phase_ == Phase::initializing) return;  // §8.2: the UART is not set up yet
  // §9.2: the stream stops when the sensor gets at least one correct byte.
  streaming_ = false;
  rx_.push_back(byte);
  while (!rx_.empty()) {
    const FrameScan scan = scan_request_frame(Bytes(rx_.data(), rx_.size()));
    if (scan.status == FrameStatus::need_more) break;
    if (scan.status == FrameStatus::complete) {
      const std::vector<std::uint8_t> frame(scan.frame.begin(), scan.frame.end());
      rx_.erase(rx_.begin(), rx_.begin() + static_cast<std::ptrdiff_t>(scan.consumed));
      handle_frame(Bytes(frame.data(), frame.size()), now);
      continue;
    }
    rx_.erase(rx_.begin(), rx_.begin() + static_cast<std::ptrdiff_t>(std::max<std::size_t>(1, scan.consumed)));
  }
}

void Firmware::reply(const Reply& answer, Nanos now) {
  auto text = encode_reply(answer);
  if (!text) return;
  pacer_.send(text->bytes(), now);
}

void Firmware::handle_frame(Bytes frame, Nanos now) {
  auto parsed = parse_request(frame);
  if (!parsed) return;  // a malformed request is ignored: the LS5 has no error reply (L14)
  const Request& request = *parsed;
  const std::uint8_t own = ram_[address::network_address];
  if (request.address != own && !request.is_broadcast()) return;
  const bool answer = request.expects_reply();
  switch (request.command) {
    case CommandId::identification: {
      auto identification =
          make_identification(config_.version_text, config_.lower_boundary_mm, config_.range_mm, config_.serial_number);
      if (identification) reply(Reply::identification_of(own, *identification), now);
      return;
    }
    case CommandId::read_parameter:
      if (!check_parameter_available(request.parameter, model_)) return;  // L25: no reply
      reply(Reply::parameter_value(own, request.parameter, ram_[request.parameter]), now);
      return;
    case CommandId::write_parameter: {
      if (!check_parameter_byte(request.parameter, request.value, model_)) return;  // L26: no reply, no change
      // L50: nor when the number the byte is part of would leave its range (limits above 50000, period 0, ...).
      const auto ram_byte = [this](std::uint8_t at) { return ram_[at]; };
      if (!check_value_after_write(request.parameter, request.value, ram_byte)) return;
      ram_[request.parameter] = request.value;
      if (answer) reply(Reply::echo(request), now);
      const std::uint8_t p = request.parameter;
      if ((p == address::baud_rate || p == address::byte_format) && phase_ == Phase::operating) {
        pending_serial_ = stored_serial_settings();  // after the echo has left the line (L28)
        pending_serial_at_ = pacer_.idle_at(now) + 1ns;
      }
      if (p == address::pre_filter || p == address::averaging_points || p == address::median_points) window_.clear();
      if (p == address::triggering || p == address::period_low || p == address::period_high) {
        if (phase_ == Phase::operating && on_) {
          next_measurement_ = ram_[address::triggering] == 0 ? now + period() : Nanos::max();
        }
      }
      return;
    }
    case CommandId::store_to_flash:
      rom_ = ram_;
      (void)save_rom();
      break;
    case CommandId::turn_on:
      if (!on_) {
        on_ = true;
        if (phase_ == Phase::operating && ram_[address::triggering] == 0) next_measurement_ = now + period();
      }
      break;
    case CommandId::turn_off:
      on_ = false;
      next_measurement_ = Nanos::max();
      update_outputs();  // §8.2: discrete outputs 0, analog holds
      break;
    case CommandId::latch_result:
      latch(now);
      break;
    case CommandId::start_stream:
      streaming_ = true;
      thinning_count_ = 0;
      return;  // no echo (L24)
    case CommandId::stop_stream:
      streaming_ = false;
      break;
    case CommandId::read_latched:
      reply(Reply::result_of(own, CommandId::read_latched, latched_), now);
      return;
    case CommandId::read_last:
      reply(Reply::result_of(own, CommandId::read_last, current_), now);
      return;
    case CommandId::restore_defaults: {
      const auto before = stored_serial_settings();
      ram_ = table_defaults();  // RAM only, until FL (L27); network address 01 from the next request (L55)
      if (answer) reply(Reply::echo(request), now);
      if (phase_ == Phase::operating && !(stored_serial_settings() == before)) {
        pending_serial_ = stored_serial_settings();
        pending_serial_at_ = pacer_.idle_at(now) + 1ns;
      }
      window_.clear();
      return;
    }
  }
  if (answer) reply(Reply::echo(request), now);
}

void Firmware::drain_pacer(Nanos now) {
  std::vector<std::uint8_t> bytes;
  while (pacer_.next_completion() <= now) {
    const Nanos done = pacer_.next_completion();
    bytes.clear();
    pacer_.take_sent(done, bytes);
    // Stamped with the settings they leave with: a W to 04/05 changes them right
    // after its echo has gone (L28), before the runtime hands the echo to the host.
    for (const auto value : bytes) {
      sent_.push_back(LineByte{done, value, serial_.baud, static_cast<std::uint8_t>(serial_.stop_bits)});
    }
  }
}

void Firmware::take_line_output(std::size_t, Nanos now, std::vector<LineByte>& out) {
  drain_pacer(now);
  std::size_t taken = 0;
  while (taken < sent_.size() && sent_[taken].done <= now) out.push_back(sent_[taken++]);
  sent_.erase(sent_.begin(), sent_.begin() + static_cast<std::ptrdiff_t>(taken));
}

// ---- Time ----

Nanos Firmware::next_deadline() const {
  Nanos next = pacer_.next_completion();
  if (!sent_.empty()) next = std::min(next, sent_.front().done);
  if (phase_ != Phase::operating) next = std::min(next, phase_until_);
  if (pending_serial_) next = std::min(next, pending_serial_at_);
  if (on_ && phase_ == Phase::operating) next = std::min(next, next_measurement_);
  return next;
}

Nanos Firmware::next_wake() const {
  // Whole runs of bytes: a host acts on a frame once its <cr> has arrived.
  Nanos next = pacer_.queued() > 0 ? pacer_.idle_at(last_now_) : Nanos::max();
  if (!sent_.empty()) next = std::min(next, sent_.back().done);
  if (phase_ != Phase::operating) next = std::min(next, phase_until_);
  if (pending_serial_) next = std::min(next, pending_serial_at_);
  if (on_ && phase_ == Phase::operating && next_measurement_ != Nanos::max()) {
    // With the stream on and the UART idle, all a host sees of the next measurement is its
    // record, which leaves 7 characters later (§8.4): run it then, in one wake instead of
    // two. advance() still measures at the measurement's own time.
    const bool record_follows = streaming_ && pacer_.queued() == 0;
    // character_time() rounds each character down: a nanosecond more each keeps the wake after the <cr>.
    const Nanos record_time = static_cast<std::int64_t>(stream_record_bytes) * (pacer_.character_time() + Nanos(1));
    next = std::min(next, record_follows ? next_measurement_ + record_time : next_measurement_);
  }
  return next;
}

void Firmware::advance(Nanos now) {
  last_now_ = std::max(last_now_, now);
  while (true) {
    Nanos event = Nanos::max();
    if (phase_ != Phase::operating) event = std::min(event, phase_until_);
    if (pending_serial_) event = std::min(event, pending_serial_at_);
    if (on_ && phase_ == Phase::operating) event = std::min(event, next_measurement_);
    if (event > now) break;
    drain_pacer(event);
    if (phase_ != Phase::operating && phase_until_ == event) {
      if (phase_ == Phase::initializing) {
        phase_ = Phase::standby;
        phase_until_ = event + standby_listen;
      } else {
        enter_operating(event);
      }
      continue;
    }
    if (pending_serial_ && pending_serial_at_ == event) {
      apply_serial(*pending_serial_, event);
      pending_serial_.reset();
      pending_serial_at_ = Nanos::max();
      continue;
    }
    measure(event, false);
  }
  drain_pacer(now);
}

// ---- Measurement pipeline (figure 8.7) ----

std::optional<double> Firmware::raw_measurement(Nanos now, bool& weak) {
  const Scene& scene = config_.scene;
  weak = false;
  const double t = seconds_of(now);
  for (const auto& dropout : scene.dropouts) {
    if (t >= dropout.start_s && t < dropout.end_s) return std::nullopt;
  }
  if (scene.dust_probability > 0 && std::uniform_real_distribution<double>(0, 1)(random_) < scene.dust_probability) {
    return std::nullopt;
  }
  if (scene.reflectivity <= 0) return std::nullopt;
  // §8.5: the exposure a target needs grows as it reflects less.
  const double needed_us = bright_exposure_us / scene.reflectivity;
  const double period_us = static_cast<double>(period().count()) / 1000.0;
  double available_us = period_us;
  if (version_.at_least(firmware_7_0)) {
    const double max_exposure = static_cast<double>(u16(address::exposure_low));
    available_us = ram_[address::priority] == 0x01 ? max_exposure : std::min(max_exposure, period_us);
  }
  if (needed_us > available_us) return std::nullopt;
  weak = needed_us > period_us;
  double position = scene.target_set ? scene.target.position_at(now) : config_.lower_boundary_mm + config_.range_mm / 2;
  const double error = digital_error_limit_mm(config_.range_mm);  // §3: ±0.15 % of the range
  const double sigma = scene.noise_mm >= 0 ? scene.noise_mm : error / 3;
  if (sigma > 0) {
    const double noise = std::normal_distribution<double>(0, sigma)(random_);
    position += std::clamp(noise, -error, error);
  }
  return position - config_.lower_boundary_mm;
}

void Firmware::measure(Nanos now, bool from_sync) {
  last_measurement_ = now;
  ++measurements_;
  bool weak = false;
  const auto distance = raw_measurement(now, weak);
  std::optional<std::uint16_t> value;
  if (distance) {
    if (auto code = code_from_distance(*distance, config_.range_mm)) value = *code;  // outside the range: no signal
  }
  // Derivative (§8.8, L11, L30).
  if (version_.at_least(firmware_8_0) && ram_[address::result_type] == 0x01 && value) {
    const std::uint16_t raw = *value;
    value = previous_raw_ ? derivative_code(raw, *previous_raw_) : derivative_zero_code;
    previous_raw_ = raw;
  } else if (value) {
    previous_raw_ = value;
  }
  // τ (§8.6, L29): the last result stands in while less than τ has passed.
  if (value) {
    last_valid_ = value;
    last_valid_at_ = now;
  } else if (last_valid_ && now - last_valid_at_ < from_ms(u16(address::signal_absence_low))) {
    value = last_valid_;
  }
  // Pre-filter (§8.7, L31).
  if (value) {
    const bool median = ram_[address::pre_filter] == 0x01;
    const std::size_t points = median ? ram_[address::median_points] : ram_[address::averaging_points];
    window_.push_back(*value);
    while (window_.size() > std::max<std::size_t>(1, points)) window_.pop_front();
    if (median) {
      std::vector<std::uint16_t> sorted(window_.begin(), window_.end());
      std::sort(sorted.begin(), sorted.end());
      value = sorted[sorted.size() / 2];
    } else {
      std::uint64_t sum = 0;
      for (const auto v : window_) sum += v;
      value = static_cast<std::uint16_t>((sum * 2 + window_.size()) / (2 * window_.size()));
    }
  } else {
    window_.clear();
  }
  current_ = classify_result_code(value ? *value : code_no_signal);
  measured_once_ = true;
  update_outputs();

  const bool sync_triggered = ram_[address::triggering] == 0x01;
  // Next cycle: the period, or longer while a weak target needs a long exposure (§8.5 sensitivity priority).
  if (!sync_triggered) {
    Nanos cycle = period();
    if (version_.at_least(firmware_7_0) && ram_[address::priority] == 0x01) {
      const double reflectivity = config_.scene.reflectivity;
      const double needed_us = reflectivity > 0 ? bright_exposure_us / reflectivity : 1e12;
      const double max_exposure = static_cast<double>(u16(address::exposure_low));
      const double used_us = std::min(needed_us, max_exposure);
      cycle = std::max(cycle, Nanos(static_cast<std::int64_t>(used_us * 1000)));
    }
    next_measurement_ = now + cycle;
  } else {
    next_measurement_ = Nanos::max();
  }
  (void)weak;

  const std::uint8_t n = std::max<std::uint8_t>(1, ram_[address::thinning]);
  // Stream (§8.4): every n-th result; none in the §8.13 case sync triggering + latching, and
  // with timer triggering a measurement the sync input started to latch is not streamed (L33).
  const bool latch_cycle = ram_[address::latching] != 0x00 && (sync_triggered || from_sync);
  if (streaming_ && !latch_cycle) {
    if (++thinning_count_ % n == 0) {
      if (pacer_.idle_at(now) <= now) {
        reply(Reply::stream_record(current_), now);
        ++records_sent_;
      } else {
        ++records_skipped_;  // the UART is still busy: the record is lost (§8.4)
      }
    }
  }
  if (model_.ethernet && ram_[address::udp_auto_stream] == 0x01 && measurements_ % n == 0) push_udp(current_);
}

void Firmware::update_outputs() {
  if (!on_) {
    oc1_ = oc2_ = false;  // §8.2; the analog output keeps its last state
    return;
  }
  // §8.10: "If the analog output is disabled, its value remains the same as it was at the last
  // measurement before the output was disabled" (L53).
  if (ram_[address::analog_enabled] == 0x01) {
    analog_ =
        analog_output(config_.analog, AnalogLimits{u16(address::analog_lower_low), u16(address::analog_upper_low)},
                      current_, last_result_code_);
  }
  if (current_.is_result()) last_result_code_ = current_.value;
  const auto outputs = decode_discrete_outputs(ram_[address::discrete_outputs]);
  if (!outputs) return;
  oc1_ = discrete_output_state(outputs->output1,
                               Swings{u16(address::output1_first_swing_low), u16(address::output1_second_swing_low)},
                               current_.value);
  oc2_ = discrete_output_state(outputs->output2,
                               Swings{u16(address::output2_first_swing_low), u16(address::output2_second_swing_low)},
                               current_.value);
  oc1_ = oc1_ && config_.discrete_outputs >= 1;
  oc2_ = oc2_ && config_.discrete_outputs >= 2;
}

void Firmware::latch(Nanos) {
  latched_ = current_;
  auto recalculation = recalculate_on_latch(ram_[address::latching], latched_, u16(address::analog_fixed_range_low),
                                            u16(address::discrete_fixed_range_low));
  if (!recalculation || !recalculation->recalculated) return;
  for (const auto& write : recalculation->writes.view()) ram_[write.address] = write.value;
  if (recalculation->to_rom) {
    if (!rom_) rom_ = delivered_rom();
    for (const auto& write : recalculation->writes.view()) (*rom_)[write.address] = write.value;
    (void)save_rom();
  }
  update_outputs();
}

void Firmware::set_sync_input(bool high, Nanos now) {
  advance(now);
  const bool rising = high && !sync_high_;
  sync_high_ = high;
  if (!rising || !on_ || phase_ != Phase::operating) return;
  const bool sync_triggered = ram_[address::triggering] == 0x01;
  if (ram_[address::latching] != 0) {
    // §8.13: the edge starts a measurement and latches it, whatever the sensor was doing.
    measure(now, true);
    latch(now);
    return;
  }
  if (!sync_triggered) return;
  // Edges faster than the measurement period are skipped (§8.13).
  if (last_measurement_ != Nanos::min() && now - last_measurement_ < period()) return;
  measure(now, true);
}

void Firmware::push_udp(const ResultCode& code) {
  UdpRecord record;
  record.state = static_cast<std::uint8_t>(udp_state::always_one | udp_state::measured);
  if (code.is_result()) {
    record.code = static_cast<std::uint16_t>(
        std::llround(code.value * static_cast<double>(udp_full_scale_code) / static_cast<double>(max_result_code)));
    record.state = static_cast<std::uint8_t>(record.state | udp_state::in_range);
  }
  if (version_.at_least(firmware_8_0) && ram_[address::result_type] == 0x01) {
    record.state = static_cast<std::uint8_t>(record.state | udp_state::derivative);
  }
  udp_packet_.records[udp_fill_++] = record;
  if (udp_fill_ < udp_record_count) return;
  udp_fill_ = 0;
  udp_packet_.serial_number = static_cast<std::uint16_t>(config_.serial_number & 0xFFFF);
  udp_packet_.lower_boundary_mm = static_cast<std::uint16_t>(std::llround(config_.lower_boundary_mm));
  udp_packet_.range_mm = static_cast<std::uint16_t>(std::llround(config_.range_mm));
  udp_packet_.counter = udp_counter_++;
  std::array<std::uint8_t, udp_packet_size> datagram{};
  if (!encode_udp_packet(udp_packet_, datagram)) return;
  ++udp_packets_;
  if (config_.udp_sink) config_.udp_sink(datagram);
}

// ---- Control socket ----

nlohmann::json Firmware::control(const nlohmann::json& request, Nanos now) {
  now = std::max(now, last_now_);
  advance(now);
  const std::string command = request.value("cmd", "");
  try {
    if (command == "outputs") {
      return {{"device", label()},
              {"analog", analog_},
              {"unit", std::string(config_.analog.unit)},
              {"analog_enabled", ram_[address::analog_enabled] == 0x01},
              {"oc1", oc1_},
              {"oc2", oc2_},
              {"laser", laser_on()},
              {"streaming", streaming_},
              {"phase", std::string(phase_name())},
              {"result", current_.value},
              {"latched", latched_.value},
              {"measurements", measurements_},
              {"udp_packets", udp_packets_}};
    }
    if (command == "sync") {
      const std::string level = request.value("level", "pulse");
      if (level == "high") {
        set_sync_input(true, now);
      } else if (level == "low") {
        set_sync_input(false, now);
      } else if (level == "pulse") {
        set_sync_input(true, now);
        set_sync_input(false, now);
      } else {
        return {{"error", "sync: level must be high, low or pulse, not '" + level + "'"}};
      }
      return {{"ok", true}, {"device", label()}, {"latched", latched_.value}, {"result", current_.value}};
    }
    if (command == "power_cycle") {
      power_cycle(now);
      return {{"ok", true}, {"device", label()}, {"phase", std::string(phase_name())}};
    }
    if (command == "move_target") {
      // The scene file's ranges, so no value the file refuses gets in this way (such as -1e308).
      const auto position = control_number(request, "position_mm", -max_scene_position_mm, max_scene_position_mm);
      if (!position) return {{"error", position.error().message}};
      const auto speed =
          control_number(request, "speed_mm_per_s", -max_scene_speed_mm_per_s, max_scene_speed_mm_per_s, 0.0);
      if (!speed) return {{"error", speed.error().message}};
      const auto reflectivity = control_number(request, "reflectivity", 0.0, 1.0, config_.scene.reflectivity);
      if (!reflectivity) return {{"error", reflectivity.error().message}};
      config_.scene.target = Motion::constant_speed(*position - *speed * seconds_of(now), *speed);
      config_.scene.target_set = true;
      config_.scene.reflectivity = *reflectivity;
      return {{"ok", true}, {"device", label()}};
    }
    if (command == "set_scene") {
      Result<Scene> scene = request.contains("file") ? load_scene(request["file"].get<std::string>())
                                                     : parse_scene(request.value("toml", ""), "control set_scene");
      if (!scene) return {{"error", scene.error().message}};
      config_.scene = std::move(*scene);
      return {{"ok", true}, {"device", label()}};
    }
  } catch (const nlohmann::json::exception& e) {
    return {{"error", command + ": " + e.what()}};
  }
  return {{"error", "unknown command '" + command + "' (LS5: outputs, sync, power_cycle, move_target, set_scene)"}};
}

}  // namespace rangekit::ls5::emulator
