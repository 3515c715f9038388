// The LS5 firmware model (docs/emulator-ls5.md; decisions: docs/conformance.md L25-L36). Here:
// creation, power and phases, the dispatch of requests and the clock; the rest by job beside it.
#include "rangekit/ls5/emulator/firmware.hpp"

#include "rangekit/core/text.hpp"

#include <algorithm>

#include "ls5/emulator/command_handlers.hpp"

namespace rangekit::ls5::emulator {

namespace {

using namespace std::chrono_literals;

constexpr Nanos init_time = 4s;          // §8.2 standby: initialisation
constexpr Nanos standby_listen = 5s;     // §8.2: 19200 8N1 waiting for commands
constexpr Nanos standby_settle = 500ms;  // §8.2: operating 0.5 s after the emitter lights up

const rangekit::SerialSettings standby_settings{19200, rangekit::Parity::none, 1};

}  // namespace

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

// ---- Power and phases ----

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
  if (held_count_ > 0) {  // a number whose pair is half written acts with its old value (L84)
    if (const ParameterInfo* parameter = find_parameter(low_address); parameter != nullptr) {
      if (parameter->part_of != LogicalValueId::none) return number(parameter->part_of);
    }
  }
  return static_cast<std::uint16_t>(ram_[low_address] | (ram_[static_cast<std::uint8_t>(low_address + 1)] << 8));
}

Nanos Firmware::period() const noexcept {
  const std::uint16_t code = std::max<std::uint16_t>(1, u16(address::period_low));
  return Nanos(static_cast<std::int64_t>(code) * 100'000);  // 0.1 ms units
}

// ---- Requests: each to its command's handler ----

void Firmware::handle_frame(Bytes frame, Nanos now) {
  auto parsed = parse_request(frame);
  if (!parsed) return;  // a malformed request is ignored: the LS5 has no error reply (L14)
  const Request& request = *parsed;
  const std::uint8_t own = ram_[address::network_address];
  if (request.address != own && !request.is_broadcast()) return;
  const Exchange exchange{request, own, request.expects_reply(), now};
  (this->*handler(request.command))(exchange);
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

}  // namespace rangekit::ls5::emulator
