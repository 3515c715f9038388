// Request/reply side of the LS5 driver: one request at a time, the reply matched
// by address, command and parameter (check_reply_answers), stray frames skipped.
#include "rangekit/ls5/driver.hpp"

#include <algorithm>
#include <array>

#include "rangekit/ls5/frame.hpp"
#include "rangekit/ls5/settings.hpp"

namespace rangekit::ls5 {
namespace {

using Clock = std::chrono::steady_clock;

// At broadcast the sensors' firmware is unknown: nothing is refused for its version.
constexpr FirmwareVersion any_version_there_is{0xFFFF, 0xFFFF};

// Addresses (IP, MAC) take every combination of their bytes; codes, period, ports do not.
bool is_full_range(const LogicalValueInfo& info) noexcept {
  return info.min == 0 && info.max == (std::uint64_t{1} << (8U * info.addresses.size())) - 1;
}

bool is_read(CommandId command) noexcept {
  return command == CommandId::identification || command == CommandId::read_parameter ||
         command == CommandId::read_last || command == CommandId::read_latched;
}

std::string wire_text(const Request& request) {
  auto encoded = encode_request(request);
  if (!encoded) return "(unencodable request)";
  std::string text(encoded->view());
  if (!text.empty() && text.back() == '\r') text.pop_back();
  return text;
}

}  // namespace

Driver::Driver(TransportPtr transport, DriverOptions options, ReopenFunction reopen)
    : transport_(std::move(transport)),
      options_(options),
      reopen_(std::move(reopen)),
      assembler_(std::make_unique<FrameAssembler>(&scan_reply_frame, 4096)) {}

std::string Driver::transport_name() const { return transport_ ? transport_->name() : "(no transport)"; }

Status Driver::reopen() {
  if (auto refused = refuse_while_streaming("reopen"); !refused) return refused;
  if (!reopen_) return make_error(Errc::unsupported, "no way to reopen " + transport_name());
  if (transport_) transport_->close();
  auto opened = reopen_();
  if (!opened) return opened.error();
  transport_ = std::move(*opened);
  assembler_->clear();
  return ok_status();
}

Result<Reply> Driver::transact_once(const Request& request) {
  auto encoded = encode_request(request);
  if (!encoded) return encoded.error();
  if (!transport_) return make_error(Errc::closed, "LS5: no transport");
  Status written = transport_->write_all(encoded->bytes());
  if (!written) return written.error();
  if (!request.expects_reply()) return Reply::echo(request);

  const auto deadline = Clock::now() + options_.timeout;
  std::array<std::uint8_t, 256> buffer{};
  for (;;) {
    FrameAssembler::Event event;
    while (assembler_->next(event)) {
      if (event.kind == FrameAssembler::Event::Kind::rejected) {
        if (event.reason != nullptr) ++rejected_frames_;
        continue;
      }
      auto reply = parse_reply(event.frame);
      if (!reply) {
        ++rejected_frames_;
        continue;
      }
      if (check_reply_answers(request, *reply)) return *reply;
      // Anything else (a stream record still in flight, another sensor's reply) is not ours.
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) break;
    auto got = transport_->read_some(buffer, left);
    if (!got) {
      if (got.error().code == Errc::timeout) break;
      return got.error();
    }
    assembler_->push(Bytes(buffer.data(), *got));
  }
  // The address in decimal, as --address and info give it (§9 "from 1 to 255"); the frame as sent (L70).
  return make_error(Errc::timeout, "LS5 at address " + std::to_string(request.address) + " on " + transport_name() +
                                       " did not answer " + wire_text(request) + " within " +
                                       std::to_string(options_.timeout.count()) +
                                       " ms: check the port, the baud rate and byte format, and the address");
}

Result<Reply> Driver::transact(const Request& request) {
  // Every request goes through here: none may interleave with the stream's reader.
  if (streaming()) {
    if (auto refused = refuse_while_streaming(wire_text(request)); !refused) return refused.error();
  }
  const int attempts = 1 + (is_read(request.command) ? options_.read_retries : 0);
  Result<Reply> reply = make_error(Errc::timeout, "not sent");
  for (int attempt = 0; attempt < attempts; ++attempt) {
    reply = transact_once(request);
    if (reply || reply.error().code != Errc::timeout) return reply;
  }
  return reply;
}

Status Driver::expect_echo(const Request& request) {
  auto reply = transact(request);
  if (!reply) return reply.error();
  return ok_status();
}

Result<Identification> Driver::identify() {
  auto reply = transact(Request::simple(options_.address, CommandId::identification));
  if (!reply) return reply.error();
  identification_ = reply->identification;
  return reply->identification;
}

Result<std::uint8_t> Driver::read_parameter(std::uint8_t parameter) {
  if (find_parameter(parameter) == nullptr) {
    return make_error(Errc::unknown_parameter, "LS5 parameter " + hex_byte(parameter) + " is not in table 9.2");
  }
  auto reply = transact(Request::read(options_.address, parameter));
  if (!reply) return reply.error();
  return reply->value;
}

Status Driver::write_parameter(std::uint8_t parameter, std::uint8_t value) {
  const ParameterWrite write{parameter, value};
  return write_parameters(std::span<const ParameterWrite>(&write, 1));
}

Status Driver::write_parameters(std::span<const ParameterWrite> writes) {
  auto sensor = context();
  if (!sensor) return sensor.error();
  SensorModel model = sensor->model;
  for (const ParameterWrite& byte : writes) {
    const ParameterInfo* info = find_parameter(byte.address);
    if (info == nullptr) {
      return make_error(Errc::unknown_parameter, "LS5 parameter " + hex_byte(byte.address) + " is not in table 9.2");
    }
    SensorModel for_byte = model;
    if (info->ethernet_only && model.firmware.at_least(firmware_12_x)) {
      for_byte.ethernet = true;  // raw writes: let the sensor decide whether it has Ethernet
    }
    Status accepted = check_parameter_byte(byte.address, byte.value, for_byte);
    if (!accepted) return accepted.error();
  }

  // Every value checked before the first byte goes out; then written value by value.
  std::vector<ParameterWrite> plan;
  std::vector<LogicalValueId> planned_values;
  for (const ParameterWrite& write : writes) {
    const ParameterInfo& parameter = *find_parameter(write.address);
    if (parameter.part_of == LogicalValueId::none) {
      plan.push_back(write);
      continue;
    }
    if (std::find(planned_values.begin(), planned_values.end(), parameter.part_of) != planned_values.end()) continue;
    planned_values.push_back(parameter.part_of);
    const LogicalValueInfo& value = logical_value_info(parameter.part_of);
    ParameterWrites given;
    std::vector<std::uint8_t> bytes;  // the value after the writes, in table order
    std::string held;                 // the bytes read from the sensor, for the message
    for (const std::uint8_t part : value.addresses) {
      std::optional<std::uint8_t> byte;
      for (const ParameterWrite& other : writes) {
        if (other.address == part) byte = other.value;  // the last one given wins
      }
      if (byte) {
        given.items[given.count++] = ParameterWrite{part, *byte};
      } else if (!is_full_range(value)) {
        if (options_.address == broadcast_address) {
          return make_error(Errc::wrong_form,
                            "LS5 parameter " + hex_byte(part) + " is part of " + std::string(value.cli_name) +
                                " and a broadcast (address 00) cannot read it to check the combined value: give "
                                "every byte of it or the setting by name");
        }
        auto read = read_parameter(part);
        if (!read) return read.error();
        byte = *read;
        held += (held.empty() ? "" : ", ") + hex_byte(part) + " = " + hex_byte(*byte);
      }
      bytes.push_back(byte.value_or(0));
    }
    if (!is_full_range(value)) {
      auto combined = combine_bytes(value, bytes);
      if (!combined) return combined.error();
      Status in_range = check_logical_value(value, *combined);
      if (!in_range) {
        std::string written;
        for (const ParameterWrite& part : given.view()) {
          written += (written.empty() ? "" : ", ") + hex_byte(part.address) + " = " + hex_byte(part.value);
        }
        // The sensor checks a value once both its bytes are written (L84): a byte alone that
        // leaves it out of range is half a pair, whose other byte belongs in the same command.
        return make_error(
            Errc::out_of_range,
            "LS5 parameter " + written + (held.empty() ? "" : " with " + held + " as the sensor holds it") + " makes " +
                std::string(value.cli_name) + " " + std::to_string(*combined) + ": " + in_range.error().message +
                (held.empty() ? ""
                              : "; give the other byte in the same command (" + held.substr(0, 2) +
                                    "=..), the sensor checks the value once both are written"));
      }
    }
    const ParameterWrites ordered = in_write_order(value, given);  // kept: view() points into it
    for (const ParameterWrite& step : ordered.view()) plan.push_back(step);
  }
  for (const ParameterWrite& step : plan) {
    Status written = write_checked(Request::write(options_.address, step.address, step.value));
    if (!written) return written;
  }
  return ok_status();
}

// One W whose value was checked; remembers what it changes in the driver's view.
Status Driver::write_checked(const Request& request) {
  if (auto refused = refuse_while_streaming("W"); !refused) return refused;
  if (request.parameter == address::result_type) derivative_results_.reset();
  return expect_echo(request);
}

Status Driver::store_to_flash() { return expect_echo(Request::simple(options_.address, CommandId::store_to_flash)); }
Status Driver::start_measuring() { return expect_echo(Request::simple(options_.address, CommandId::turn_on)); }
Status Driver::stop_measuring() { return expect_echo(Request::simple(options_.address, CommandId::turn_off)); }
Status Driver::latch() { return expect_echo(Request::simple(options_.address, CommandId::latch_result)); }
Status Driver::send_stop_stream() { return expect_echo(Request::simple(options_.address, CommandId::stop_stream)); }
Status Driver::restore_defaults() {
  if (auto refused = refuse_while_streaming("DF"); !refused) return refused;
  derivative_results_.reset();  // 0E goes back to its default: asked again when needed
  Status restored = expect_echo(Request::simple(options_.address, CommandId::restore_defaults));
  // The echo leaves at the old address; from the next request the sensor answers at
  // table 9.2's default network address 01 (L55), so this driver follows it.
  if (restored && options_.address != broadcast_address) options_.address = default_network_address;
  return restored;
}

Result<bool> Driver::results_are_derivative() {
  if (auto refused = refuse_while_streaming("results_are_derivative"); !refused) return refused.error();
  if (derivative_results_) return *derivative_results_;
  auto sensor = context();
  if (!sensor) return sensor.error();
  if (!sensor->model.firmware.at_least(find_parameter(address::result_type)->since)) {
    derivative_results_ = false;  // no 0E before LS5.8.0 (§8.8): always the pure form
    return false;
  }
  auto type = transact(Request::read(options_.address, address::result_type));
  if (!type) return type.error();
  derivative_results_ = type->value == 0x01;
  return *derivative_results_;
}

Result<Measurement> Driver::to_measurement(ResultCode code) {
  Measurement measurement;
  measurement.code = code;
  measurement.derivative = derivative_results_.value_or(false);
  if (code.is_result() && identification_ && identification_->range_mm > 0) {
    if (measurement.derivative) {
      measurement.derivative_mm = derivative_mm(code.value, identification_->range_mm);  // formula 8.2
    } else {
      measurement.distance_mm = distance_mm(code.value, identification_->range_mm);  // formula 8.1
    }
  }
  return measurement;
}

Result<Measurement> Driver::read_latched() {
  auto derivative = results_are_derivative();  // how to read the code (§8.9)
  if (!derivative) return derivative.error();
  auto reply = transact(Request::simple(options_.address, CommandId::read_latched));
  if (!reply) return reply.error();
  return to_measurement(reply->result);
}

Result<Measurement> Driver::read_last() {
  auto derivative = results_are_derivative();  // how to read the code (§8.9)
  if (!derivative) return derivative.error();
  auto reply = transact(Request::simple(options_.address, CommandId::read_last));
  if (!reply) return reply.error();
  return to_measurement(reply->result);
}

Result<SettingContext> Driver::context() {
  if (auto refused = refuse_while_streaming("context"); !refused) return refused.error();
  SettingContext context;
  if (options_.address == broadcast_address) {
    context.model.firmware = options_.assumed_firmware.value_or(any_version_there_is);
    context.model.ethernet = true;
    return context;
  }
  if (options_.assumed_firmware) {
    context.model.firmware = *options_.assumed_firmware;
  } else {
    if (!identification_) {
      auto identified = identify();
      if (!identified) return identified.error();
    }
    context.model.firmware = identification_->version.value_or(any_firmware);
  }
  if (identification_) context.range_mm = identification_->range_mm;
  context.model.ethernet = ethernet_.value_or(context.model.firmware.at_least(firmware_12_x));
  return context;
}

Result<SensorInfo> Driver::info() {
  auto identified = identify();
  if (!identified) return identified.error();
  SensorInfo info{options_.address, *identified, false};
  if (identified->version && identified->version->at_least(firmware_12_x)) {
    // R70 (UDP auto-stream) exists only on Ethernet sensors: no reply means none (L26).
    auto udp = transact(Request::read(options_.address, address::udp_auto_stream));
    if (!udp && udp.error().code != Errc::timeout) return udp.error();
    info.ethernet = udp.ok();
    ethernet_ = info.ethernet;
  }
  return info;
}

Result<SettingReading> Driver::get(const HostSetting& setting) {
  auto sensor = context();
  if (!sensor) return sensor.error();
  Status available = check_setting_available(setting, sensor->model);
  if (!available) return available.error();
  SettingReading reading{&setting, {}, {}};
  for (const std::uint8_t parameter : setting.addresses()) {
    auto value = read_parameter(parameter);
    if (!value) return value.error();
    reading.bytes.push_back(*value);
  }
  auto text = format_setting(setting, reading.bytes, *sensor);
  if (!text) return text.error();
  reading.text = std::move(*text);
  return reading;
}

Result<SettingReading> Driver::get(std::string_view name) {
  const HostSetting* setting = find_host_setting(name);
  if (setting == nullptr)
    return make_error(Errc::unknown_parameter, "no LS5 setting named '" + std::string(name) + "'");
  return get(*setting);
}

Status Driver::set(const HostSetting& setting, std::string_view text) {
  auto sensor = context();
  if (!sensor) return sensor.error();
  auto writes = encode_setting(setting, text, *sensor);  // every byte checked before the first is sent
  if (!writes) return writes.error();
  // In an order the sensor accepts from any value it may hold (L50, L62).
  const ParameterWrites ordered =
      setting.value == LogicalValueId::none ? *writes : in_write_order(logical_value_info(setting.value), *writes);
  for (const ParameterWrite& write : ordered.view()) {
    Status written = write_checked(Request::write(options_.address, write.address, write.value));
    if (!written) return written.error();
  }
  if (setting.parameter == address::network_address && setting.value == LogicalValueId::none &&
      options_.address != broadcast_address) {
    options_.address = writes->items[0].value;  // L28: the next request goes to the new address
  }
  return ok_status();
}

Result<std::vector<Driver::NamedValue>> Driver::read_all_settings() {
  auto identity = info();  // firmware, range and Ethernet decide what exists
  if (!identity) return identity.error();
  auto sensor = context();
  if (!sensor) return sensor.error();
  std::vector<NamedValue> values;
  for (const HostSetting& setting : host_setting_table()) {
    if (!setting.canonical || !check_setting_available(setting, sensor->model)) continue;
    auto reading = get(setting);
    if (!reading) return reading.error();
    values.push_back({std::string(setting.name), reading->text, setting.unit});
    // The mm form of a code value, from the same bytes.
    if (const HostSetting* in_mm = find_host_setting(std::string(setting.name) + "-mm")) {
      if (auto mm = format_setting(*in_mm, reading->bytes, *sensor))
        values.push_back({std::string(in_mm->name), *mm, in_mm->unit});
    }
  }
  return values;
}

Status Driver::set(std::string_view name, std::string_view text) {
  const HostSetting* setting = find_host_setting(name);
  if (setting == nullptr)
    return make_error(Errc::unknown_parameter, "no LS5 setting named '" + std::string(name) + "'");
  return set(*setting, text);
}

}  // namespace rangekit::ls5
