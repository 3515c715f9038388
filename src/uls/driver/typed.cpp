// The typed calls of the ULS driver: each is a get or set of the command
// table's row with the value converted to and from its readable type.
#include <array>
#include <cstdio>

#include "rangekit/core/text.hpp"
#include "rangekit/uls/describe.hpp"
#include "rangekit/uls/driver.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/formulas.hpp"

namespace rangekit::uls {

namespace {

Error bad_reply(std::string_view mnemonic, const std::vector<std::string>& values) {
  std::string text = "unexpected reply to $" + std::string(mnemonic) + ":";
  for (const auto& value : values) text += " '" + value + "'";
  return make_error(Errc::invalid_frame, text);
}

Result<std::uint64_t> one_unsigned(Result<std::vector<std::string>> values, std::string_view mnemonic,
                                   std::size_t index = 0) {
  if (!values) return std::move(values).error();
  if (values->size() <= index) return bad_reply(mnemonic, *values);
  auto number = text::parse_unsigned((*values)[index]);
  if (!number) return bad_reply(mnemonic, *values);
  return *number;
}

Result<double> one_decimal(Result<std::vector<std::string>> values, std::string_view mnemonic) {
  if (!values) return std::move(values).error();
  if (values->size() != 1) return bad_reply(mnemonic, *values);
  auto number = text::parse_decimal((*values)[0]);
  if (!number) return bad_reply(mnemonic, *values);
  return *number;
}

template <class Enum>
Result<Enum> one_enum(Result<std::uint64_t> number, std::optional<Enum> (*convert)(std::uint64_t),
                      std::string_view mn) {
  if (!number) return std::move(number).error();
  auto value = convert(*number);
  if (!value) return make_error(Errc::out_of_range, "$" + std::string(mn) + " replied " + std::to_string(*number));
  return *value;
}

std::string number_text(std::uint64_t value) { return std::to_string(value); }

}  // namespace

Result<std::string> Driver::version() {
  auto values = get("ID");
  if (!values) return std::move(values).error();
  std::string text;
  for (const auto& value : *values) text += (text.empty() ? "" : ",") + value;
  return text;
}

Result<StatusInfo> Driver::status() {
  auto number = one_unsigned(get("US"), "US");
  if (!number) return std::move(number).error();
  return decode_status(static_cast<std::uint8_t>(*number));
}

Result<UnitInfo> Driver::info() {
  UnitInfo info;
  auto text = version();
  if (!text) return std::move(text).error();
  info.version = *text;
  auto state = status();
  if (!state) return std::move(state).error();
  info.status = *state;
  info.address = options_.address;
  return info;
}

Status Driver::start_measuring() {
  Status started = action("GO");
  // A unit already measuring answers GO with 31 "Instrument Is Already Measuring" (U77): as asked.
  if (!started && started.error().device_code == error_number::already_measuring) return ok_status();
  return started;
}
Status Driver::stop_measuring() {
  stop_stream(AfterStream::keep_measuring);  // a running stream ends first; the unit is stopped below
  return action("ST");
}
Result<bool> Driver::stop_if_measuring() {
  auto state = status();
  if (!state) return std::move(state).error();
  if (!state->measuring()) return false;
  if (auto stopped = stop_measuring(); !stopped) return stopped.error();
  return true;
}
Status Driver::save() { return action("SU"); }

Result<Sample> Driver::measure() {
  if (streaming_) return make_error(Errc::unsupported, "measure() while streaming: read the stream instead");
  bool known = false;
  {
    std::lock_guard lock(state_mutex_);
    known = context_known_;
  }
  // The settings a BM line reads by, from the unit once; a set through this driver forgets them.
  if (!known) {
    if (auto context = read_context(); !context) return context.error();
  }
  Sample sample;
  auto done = transact(*find_command("BM"), {}, Expect::measurement, 1, options_.measure_timeout, &sample);
  if (!done) return done.error();
  return sample;
}

Result<Mode> Driver::mode() { return one_enum<Mode>(one_unsigned(get("MM"), "MM"), &to_mode, "MM"); }
Status Driver::set_mode(Mode value) { return set("MM", number_text(wire_value(value))); }
Result<DisplayMode> Driver::display_mode() {
  return one_enum<DisplayMode>(one_unsigned(get("DM"), "DM"), &to_display_mode, "DM");
}
Status Driver::set_display_mode(DisplayMode value) { return set("DM", number_text(wire_value(value))); }
Result<Units> Driver::units() {
  auto value = one_enum<Units>(one_unsigned(get("MU"), "MU"), &to_units, "MU");
  if (value) {
    std::lock_guard lock(state_mutex_);
    units_ = *value;
  }
  return value;
}
Status Driver::set_units(Units value) { return set("MU", number_text(wire_value(value))); }
Result<PowerLevel> Driver::power() {
  return one_enum<PowerLevel>(one_unsigned(get("PL"), "PL"), &to_power_level, "PL");
}
Status Driver::set_power(PowerLevel value) { return set("PL", number_text(wire_value(value))); }
Result<OutputPort> Driver::output_port() {
  return one_enum<OutputPort>(one_unsigned(get("MO"), "MO"), &to_output_port, "MO");
}
Status Driver::set_output_port(OutputPort value) { return set("MO", number_text(wire_value(value))); }
Result<BinSize> Driver::bin_size() { return one_enum<BinSize>(one_unsigned(get("BS"), "BS"), &to_bin_size, "BS"); }
Status Driver::set_bin_size(BinSize value) { return set("BS", number_text(wire_value(value))); }

Result<std::array<std::uint32_t, 3>> Driver::prf() {
  auto values = get("PF");
  if (!values) return std::move(values).error();
  if (values->size() != 3) return bad_reply("PF", *values);
  std::array<std::uint32_t, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) {
    auto number = text::parse_unsigned((*values)[i], 5);
    if (!number) return bad_reply("PF", *values);
    out[i] = static_cast<std::uint32_t>(*number);
  }
  return out;
}
Status Driver::set_prf(std::uint32_t hz) { return set("PF", number_text(hz)); }
Status Driver::set_prf(std::uint32_t averaging_hz, std::uint32_t binning_hz, std::uint32_t look_down_hz) {
  const std::array<std::string, 3> texts{number_text(averaging_hz), number_text(binning_hz), number_text(look_down_hz)};
  const std::array<std::string_view, 3> values{texts[0], texts[1], texts[2]};
  return set("PF", values);
}

Result<std::array<std::uint32_t, 2>> Driver::pulses_per_measurement() {
  auto values = get("PO");
  if (!values) return std::move(values).error();
  if (values->size() != 2) return bad_reply("PO", *values);
  std::array<std::uint32_t, 2> out{};
  for (std::size_t i = 0; i < 2; ++i) {
    auto number = text::parse_unsigned((*values)[i], 5);
    if (!number) return bad_reply("PO", *values);
    out[i] = static_cast<std::uint32_t>(*number);
  }
  return out;
}
Status Driver::set_pulses_per_measurement(std::uint32_t pulses) { return set("PO", number_text(pulses)); }
Status Driver::set_pulses_per_measurement(std::uint32_t averaging, std::uint32_t binning) {
  const std::array<std::string, 2> texts{number_text(averaging), number_text(binning)};
  const std::array<std::string_view, 2> values{texts[0], texts[1]};
  return set("PO", values);
}

Result<std::uint32_t> Driver::averaging_weight() {
  auto number = one_unsigned(get("AW"), "AW");
  if (!number) return std::move(number).error();
  return static_cast<std::uint32_t>(*number);
}
Status Driver::set_averaging_weight(std::uint32_t pulses) { return set("AW", number_text(pulses)); }
Result<std::uint32_t> Driver::bin_threshold() {
  auto number = one_unsigned(get("BH"), "BH");
  if (!number) return std::move(number).error();
  return static_cast<std::uint32_t>(*number);
}
Status Driver::set_bin_threshold(std::uint32_t hits) { return set("BH", number_text(hits)); }

Result<std::uint32_t> Driver::baud(BaudPort port) {
  const std::string port_text = number_text(wire_value(port));
  const std::array<std::string_view, 1> arguments{port_text};
  auto number = one_unsigned(get("BR", arguments), "BR", 1);
  if (!number) return std::move(number).error();
  return static_cast<std::uint32_t>(*number);
}
Status Driver::set_baud(BaudPort port, std::uint32_t baud) {
  const std::array<std::string, 2> texts{number_text(wire_value(port)), number_text(baud)};
  const std::array<std::string_view, 2> values{texts[0], texts[1]};
  return set("BR", values);
}

Result<std::uint8_t> Driver::unit_address() {
  auto number = one_unsigned(get("UA"), "UA");
  if (!number) return std::move(number).error();
  auto address = unit_address_char(*number);
  if (!address) return make_error(Errc::out_of_range, "$UA replied " + std::to_string(*number));
  return *address;
}
Status Driver::set_unit_address(std::uint8_t address) {
  const std::string value(1, static_cast<char>(address));
  return set("UA", value);
}

Result<std::uint64_t> Driver::trip_timeout_pulses() {
  auto values = get("TT");
  if (!values) return std::move(values).error();
  if (values->size() != 1) return bad_reply("TT", *values);
  auto pulses = parse_trip_timeout((*values)[0]);
  if (!pulses) return bad_reply("TT", *values);
  return *pulses;
}
Status Driver::set_trip_timeout_pulses(std::uint64_t pulses) {
  const HexText hex = to_hex_text(pulses);
  return set("TT", hex.view());
}

Result<bool> Driver::flag(std::string_view mnemonic) {
  auto number = one_unsigned(get(mnemonic), mnemonic);
  if (!number) return std::move(number).error();
  return *number != 0;
}
Status Driver::set_flag(std::string_view mnemonic, bool on) { return set(mnemonic, on ? "1" : "0"); }

Result<double> Driver::distance_m(std::string_view mnemonic) {
  auto units = cached_units();
  if (!units) return units.error();
  auto value = one_decimal(get(mnemonic), mnemonic);
  if (!value) return value;
  return to_metres(*value, *units);
}

Status Driver::set_distance_m(std::string_view mnemonic, double metres) {
  auto units = cached_units();
  if (!units) return units.error();
  auto text = format_distance(from_metres(metres, *units), *units);
  if (!text) return make_error(Errc::out_of_range, std::string(mnemonic) + ": distance is not a finite number");
  return set(mnemonic, text->view());
}

Result<double> Driver::fault_current_ma() { return one_decimal(get("AF"), "AF"); }
Status Driver::set_fault_current_ma(double milliamps) { return set("AF", decimal_text(milliamps)); }
Result<double> Driver::fault_timeout_s() { return one_decimal(get("AT"), "AT"); }
Status Driver::set_fault_timeout_s(double seconds) { return set("AT", decimal_text(seconds)); }

Result<MeasurementContext> Driver::read_context() {
  MeasurementContext context;
  auto mode_value = mode();
  if (!mode_value) return mode_value.error();
  context.mode = *mode_value;
  auto display = display_mode();
  if (!display) return display.error();
  context.display = *display;
  auto units_value = units();
  if (!units_value) return units_value.error();
  context.units = *units_value;
  auto tbe = time_between_events();
  if (!tbe) return tbe.error();
  context.time_between_events = *tbe;
  std::lock_guard lock(state_mutex_);
  context_ = context;
  context_known_ = true;
  unit_contexts_[context_key(options_.address)] = context;
  return context;
}

}  // namespace rangekit::uls
