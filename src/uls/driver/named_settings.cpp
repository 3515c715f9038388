#include "rangekit/uls/named_settings.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "rangekit/core/text.hpp"
#include "rangekit/uls/bus.hpp"
#include "rangekit/uls/describe.hpp"
#include "rangekit/uls/formulas.hpp"
#include "rangekit/uls/frame.hpp"
#include "rangekit/uls/host_config.hpp"

namespace rangekit::uls::named {

namespace {

std::string lower(std::string_view text) {
  std::string out;
  for (const char c : text) out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  return out;
}

std::optional<std::uint32_t> named_value(const CommandInfo& command, std::string_view typed) {
  const std::string want = value_key(typed);
  if (command.kind == ValueKind::flag) {
    if (want == "on" || want == "true" || want == "yes") return 1;
    if (want == "off" || want == "false" || want == "no") return 0;
  }
  if (command.mnemonic == "MU") {
    if (want == "m" || want == "metre" || want == "meter" || want == "meters") return 1;
    if (want == "ft" || want == "foot") return 0;
  }
  std::optional<std::uint32_t> prefixed;
  int prefix_matches = 0;
  for (const ValueName& entry : command.value_names) {
    const std::string name = value_key(entry.name);
    if (name == want) return entry.value;
    // Leading words that name one value only: "rs485", "range-and".
    if (name.rfind(want + "-", 0) == 0) {
      prefixed = entry.value;
      ++prefix_matches;
    }
  }
  return prefix_matches == 1 ? prefixed : std::nullopt;
}

std::string distance_field(double metres, Units units) {
  auto text = format_distance(from_metres(metres, units), units);
  return text ? std::string(text->view()) : std::string("nan");
}

}  // namespace

std::string setting_key(const CommandInfo& command) {
  std::string name(command.cli_name);
  if (command.is_distance()) return name + "-m";
  switch (command.kind) {
    case ValueKind::milliamps:
      return name + "-ma";
    case ValueKind::seconds:
    case ValueKind::hex_pulses:  // read and written in seconds (U21)
      return name + "-s";
    case ValueKind::prf_list:
      return name + "-hz";
    default:
      return name;
  }
}

namespace {

struct NamedSetting {
  std::string key;
  const CommandInfo* command;
  std::string port;  // BR: "0" configuration port, "1" output port (§8 Set/Get Baud Rate)
};

// Every name get prints, in table order: BR once per port.
std::vector<NamedSetting> named_settings() {
  std::vector<NamedSetting> names;
  for (const CommandInfo& command : command_table()) {
    if (command.access == Access::action || command.mnemonic == "BM") continue;
    if (command.kind == ValueKind::baud_with_port) {
      names.push_back({"baud-configuration", &command, "0"});
      names.push_back({"baud-output", &command, "1"});
    } else {
      names.push_back({setting_key(command), &command, ""});
    }
  }
  return names;
}

std::string names_for(Purpose purpose) {
  std::string names;
  for (const NamedSetting& named : named_settings()) {
    if (purpose == Purpose::set ? !named.command->has_set() : !named.command->has_get()) continue;
    names += (names.empty() ? "" : ", ") + named.key;
  }
  return names;
}

Result<Target> lookup(std::string_view name) {
  const std::string want = lower(name);
  for (const NamedSetting& named : named_settings())
    if (named.key == want) return Target{named.command, false, named.port};
  // The earlier spelling without the unit ("prf", "long-gate") stays accepted.
  if (const CommandInfo* command = find_command_by_cli_name(want); command != nullptr)
    return Target{command, false, ""};
  if (name.size() >= 2 && name.size() <= 4) {
    bool letters = true;
    for (const char c : name) letters = letters && std::isalpha(static_cast<unsigned char>(c)) != 0;
    if (const CommandInfo* command = letters ? find_command(name) : nullptr; command != nullptr)
      return Target{command, true, ""};
  }
  return make_error(Errc::unknown_command, "unknown setting '" + std::string(name) + "'");
}

}  // namespace

std::string writable_names() { return names_for(Purpose::set); }

Result<Target> find_setting(std::string_view name, Purpose purpose) {
  auto target = lookup(name);
  if (!target) {
    std::vector<std::string> keys;
    for (const NamedSetting& named : named_settings()) keys.push_back(named.key);
    if (const auto meant = text::closest(name, keys)) {
      return make_error(Errc::unknown_command, target.error().message + "; did you mean '" + *meant +
                                                   "'? (`rangekit uls " + (purpose == Purpose::set ? "set" : "get") +
                                                   " --help` lists every name)");
    }
    return make_error(Errc::unknown_command,
                      target.error().message + "; " + (purpose == Purpose::set ? "writable names: " : "names: ") +
                          names_for(purpose) + " (or the 2-letter mnemonics: `rangekit tables uls-commands`)");
  }
  if (purpose == Purpose::set && !target->command->has_set())
    return make_error(Errc::wrong_form, "'" + std::string(name) + "' is read-only (" +
                                            std::string(target->command->mnemonic) +
                                            " is only read); writable names: " + writable_names());
  return target;
}

namespace {

// The value name a typo most likely meant ("binnig" -> "binning").
std::optional<std::string> meant_value(const CommandInfo& command, std::string_view typed) {
  std::vector<std::string> keys;
  for (const ValueName& entry : command.value_names) keys.push_back(value_key(entry.name));
  return text::closest(typed, keys);
}

// Values named by a quantity ("4 inches"): a bare number there could be the quantity or the
// code, so it is neither.
bool values_are_quantities(const CommandInfo& command) {
  return !command.value_names.empty() && !command.value_names.front().name.empty() &&
         std::isdigit(static_cast<unsigned char>(command.value_names.front().name.front())) != 0;
}

std::string bare_number_refusal(const CommandInfo& command, const std::string& field) {
  std::string quantity(command.cli_name);  // "bin size"
  std::replace(quantity.begin(), quantity.end(), '-', ' ');
  const std::string what = std::string(command.cli_name) + ": '" + field + "' is not a " + quantity + ": give ";
  const std::string code = ", or the code as " + std::string(command.mnemonic) + "=" + field;
  std::string names;
  for (const ValueName& entry : command.value_names) {
    const std::string name = value_key(entry.name);
    // "4 inches" for a typed 4: the quantity the user most likely meant.
    if (entry.name.substr(0, entry.name.find(' ')) == field) {
      std::string refusal = what;
      refusal += "its unit, " + name;
      refusal += " (" + std::string(command.mnemonic) + " " + std::to_string(entry.value) + ")";
      return refusal + code;
    }
    names += (names.empty() ? "" : ", ") + name;
  }
  return what + "one of " + names + code;
}

}  // namespace

namespace {

// Seconds with up to 4 decimals, trailing zeros dropped: "360", "0.0003".
std::string seconds_text(double seconds) {
  std::array<char, 64> buffer{};
  std::snprintf(buffer.data(), buffer.size(), "%.4f", seconds);
  std::string text = buffer.data();
  while (text.back() == '0') text.pop_back();
  if (text.back() == '.') text.pop_back();
  return text;
}

}  // namespace

Result<std::vector<std::string>> to_fields(const Target& target, std::string_view value, Units device_units) {
  const CommandInfo& command = *target.command;
  std::vector<std::string> fields;
  std::string_view rest = value;
  while (true) {
    const auto comma = rest.find(',');
    fields.emplace_back(rest.substr(0, comma));
    if (comma == std::string_view::npos) break;
    rest = rest.substr(comma + 1);
  }
  if (target.raw) return fields;
  if (!target.port.empty()) fields.insert(fields.begin(), target.port);  // baud-output=9600 is BR,1,9600
  for (auto& field : fields) {
    if ((command.kind == ValueKind::flag || command.kind == ValueKind::enumeration) &&
        !text::parse_unsigned(field).has_value()) {
      if (auto number = named_value(command, field)) {
        field = std::to_string(*number);
      } else if (auto meant = meant_value(command, field)) {
        return make_error(Errc::out_of_range, std::string(command.cli_name) + ": '" + field + "' is no value of " +
                                                  std::string(command.cli_name) + "; did you mean '" + *meant +
                                                  "'? (allowed: " + allowed_values(command, Units::metres) + ")");
      }
      // else left as typed: validation names the allowed values
    } else if (command.kind == ValueKind::address_char && field.size() > 1) {
      // The family's spelling of a byte no terminal shows (0x9C, as `get` prints it): the wire
      // takes the byte itself.
      if (auto byte = parse_unit_address(field)) field = std::string(1, static_cast<char>(*byte));
    } else if (command.kind == ValueKind::enumeration && values_are_quantities(command)) {
      return make_error(Errc::out_of_range, bare_number_refusal(command, field));
    } else if (command.is_distance()) {
      // Readable distances are metres; a trailing "ft" or "m" says otherwise (U64).
      std::string number = field;
      Units typed = Units::metres;
      if (number.size() > 2 && number.substr(number.size() - 2) == "ft") {
        number.resize(number.size() - 2);
        typed = Units::feet;
      } else if (number.size() > 1 && number.back() == 'm') {
        number.pop_back();
      }
      auto parsed = text::parse_decimal(number);
      if (!parsed)
        return make_error(Errc::out_of_range, std::string(command.cli_name) + ": '" + field + "' is not a distance");
      // A limit typed in either unit stays that limit in the unit's own (U76): 5577.43ft is 1700 m.
      field = distance_field(distance_to_metres(*parsed, typed, command.min, command.max), device_units);
    } else if (command.kind == ValueKind::hex_pulses) {
      // Readable trip-timeout is seconds (§8: "seconds x 3000", U21).
      std::string number = field;
      if (!number.empty() && number.back() == 's') number.pop_back();
      auto seconds = text::parse_decimal(number);
      if (!seconds || *seconds < 0)
        return make_error(Errc::out_of_range, "trip-timeout: '" + field + "' is not a number of seconds");
      if (*seconds > trip_timeout_seconds(max_trip_timeout_pulses))
        return make_error(Errc::out_of_range, "trip-timeout: " + field + " s is more than the unit counts (" +
                                                  seconds_text(trip_timeout_seconds(max_trip_timeout_pulses)) + " s)");
      field = std::string(to_hex_text(trip_timeout_pulses(*seconds)).view());
    }
  }
  return fields;
}

namespace {

bool is_numeric(const CommandInfo& command) {
  switch (command.kind) {
    case ValueKind::unsigned_int:
    case ValueKind::distance:
    case ValueKind::signed_distance:
    case ValueKind::milliamps:
    case ValueKind::seconds:
    case ValueKind::hex_pulses:
    case ValueKind::prf_list:
    case ValueKind::ppm_list:
    case ValueKind::baud_with_port:
      return true;
    default:
      return false;
  }
}

}  // namespace

std::string without_unit(const CommandInfo& command, const std::string& readable_text) {
  if (command.kind == ValueKind::hex_pulses) {  // "1080000 pulses" -> "360" (seconds x 3000, §8)
    const auto space = readable_text.find(' ');
    if (auto pulses = text::parse_unsigned(readable_text.substr(0, space)))
      return seconds_text(trip_timeout_seconds(*pulses));
    return readable_text;
  }
  for (const std::string_view unit : {" mA", " m", " s", " Hz"}) {
    if (readable_text.size() > unit.size() && readable_text.ends_with(unit))
      return readable_text.substr(0, readable_text.size() - unit.size());
  }
  return readable_text;
}

Reading describe_reply(const CommandInfo& command, const std::vector<std::string>& values, Units device_units) {
  auto joined = [&values] {
    std::string text;
    for (const auto& value : values) text += (text.empty() ? "" : ",") + value;
    return text;
  };
  if (command.mnemonic == "ID") return {joined(), false};
  if (command.mnemonic == "US" && values.size() == 1) {
    const auto number = text::parse_unsigned(values[0]).value_or(0);
    const auto name = command.value_name(static_cast<std::uint32_t>(number));
    return {name.empty() ? values[0] : std::string(name), false};
  }
  if (command.mnemonic == "BR" && values.size() == 2) return {values[1], true};
  if (command.mnemonic == "UA" && values.size() == 1) {
    // As the family writes it everywhere ('A', or 0x9C beyond what a terminal shows), so that
    // `set address=` takes back what `get` printed.
    auto address = unit_address_char(text::parse_unsigned(values[0]).value_or(0));
    if (address) return {address_text(*address), false};
    return {values[0], false};
  }
  auto setting = from_wire(command, values, device_units);
  if (!setting) return {joined(), false};
  return {without_unit(command, readable(*setting)), is_numeric(command)};
}

// --- On a unit -------------------------------------------------------------------

Result<std::vector<Value>> read_setting(Driver& driver, const Target& target, Units device_units) {
  const CommandInfo& command = *target.command;
  std::vector<Value> lines;
  if (command.mnemonic == "BR") {
    for (const char* each : {"0", "1"}) {
      if (!target.port.empty() && target.port != each) continue;
      const std::array<std::string_view, 1> argument{each};
      auto values = driver.get("BR", argument);
      if (!values) return values.error();
      lines.push_back({each[0] == '0' ? "baud-configuration" : "baud-output",
                       {values->at(1), true},
                       "BR," + std::string(each) + "=" + values->at(1)});
    }
    return lines;
  }
  auto values = driver.get(command.mnemonic);
  if (!values) {
    if (command.mnemonic == "UA" && values.error().device_code == 82) {
      lines.push_back({"address", {"unassigned", false}, "UA: error 82, Unit Address Not Assigned"});
      return lines;
    }
    return values.error();
  }
  std::string wire;
  for (const auto& value : *values) wire += (wire.empty() ? "" : ",") + value;
  if (command.kind == ValueKind::hex_pulses && values->size() == 1) {
    if (auto pulses = parse_trip_timeout(values->front())) wire += " (" + std::to_string(*pulses) + " pulses)";
  }
  lines.push_back({setting_key(command), describe_reply(command, *values, device_units),
                   std::string(command.mnemonic) + "=" + wire});
  return lines;
}

std::vector<Target> readable_targets() {
  std::vector<Target> targets;
  for (const CommandInfo& command : command_table())
    if (command.has_get() && command.mnemonic != "BM") targets.push_back(Target{&command, false, ""});
  return targets;
}

Result<std::vector<Value>> read_all(Driver& driver) {
  auto units = driver.units();
  if (!units) return units.error();
  std::vector<Value> all;
  for (const Target& target : readable_targets()) {
    auto lines = read_setting(driver, target, *units);
    if (!lines) return lines.error();
    all.insert(all.end(), lines->begin(), lines->end());
  }
  return all;
}

Result<std::vector<Assignment>> plan(const std::vector<std::pair<std::string, std::string>>& pairs) {
  std::vector<Assignment> work;
  for (const auto& [name, value] : pairs) {
    auto target = find_setting(name, Purpose::set);
    if (!target) return target.error();
    work.push_back({*target, value});
  }
  // Every value is checked before the first is sent (distances again once MU is known). A
  // refusal starts with the name as it was given ("short-gate-m: ..."), so a caller with
  // several values knows which one.
  const auto named_after = [&](const std::string& given, Error error) {
    if (error.message.rfind(given, 0) != 0) error.message = given + ": " + error.message;
    return error;
  };
  for (std::size_t i = 0; i < work.size(); ++i) {
    const auto& [target, value] = work[i];
    auto fields = to_fields(target, value, Units::metres);
    if (!fields) return named_after(pairs[i].first, fields.error());
    const bool distance = target.command->is_distance();
    const std::vector<std::string_view> views(fields->begin(), fields->end());
    if (const Verdict verdict = validate_request(*target.command, views, Units::metres);
        !verdict.ok() && !(distance && target.raw))
      return named_after(pairs[i].first, local_refusal(*target.command, value, verdict.error, Units::metres));
  }
  std::stable_partition(work.begin(), work.end(), [](const Assignment& item) {
    const std::string_view mnemonic = item.target.command->mnemonic;
    return mnemonic != "BR" && mnemonic != "UA";
  });
  return work;
}

std::string assignment_name(const Target& target) {
  if (target.raw) return std::string(target.command->mnemonic);
  if (target.port == "0") return "baud-configuration";
  if (target.port == "1") return "baud-output";
  return setting_key(*target.command);
}

Status apply(Driver& driver, const std::vector<Assignment>& assignments,
             const std::function<void(const Written&)>& written) {
  std::optional<Units> units;
  for (const Assignment& assignment : assignments) {
    const Target& target = assignment.target;
    if (target.command->is_distance() && !units) {
      auto read = driver.units();
      if (!read) return read.error();
      units = *read;
    }
    auto fields = to_fields(target, assignment.value, units.value_or(Units::metres));
    if (!fields) return fields.error();
    const std::vector<std::string_view> views(fields->begin(), fields->end());
    if (auto done = driver.set(target.command->mnemonic, views); !done) return done;
    if (written) written(Written{&assignment, *fields});
    if (target.command->mnemonic == "MU") units.reset();
  }
  return ok_status();
}

namespace {

// Each accepted value read back as `get` prints it and compared with what was sent.
Status verify(Driver& driver, const std::vector<Written>& written) {
  if (written.empty()) return ok_status();
  auto units = driver.units();
  if (!units) return units.error();
  for (const Written& one : written) {
    const CommandInfo& command = *one.assignment->target.command;
    if (!command.has_get()) continue;  // PT: set only
    auto lines = read_setting(driver, one.assignment->target, *units);
    if (!lines) return lines.error();
    const std::string wanted = describe_reply(command, one.fields, *units).text;
    const std::string& read = lines->front().reading.text;
    // PF/PO with one value set the current mode's entry of the list they read back as (U14, U15).
    const bool one_of_list = one.fields.size() == 1 && ("," + read + ",").find("," + wanted + ",") != std::string::npos;
    if (read != wanted && !one_of_list) {
      std::string message = assignment_name(one.assignment->target);
      message += " reads back as " + read;
      message += ", not " + wanted;
      return make_error(Errc::device_error, message);
    }
  }
  return ok_status();
}

}  // namespace

Result<bool> write(Driver& driver, const std::vector<Assignment>& assignments,
                   const std::function<void(const Written&)>& written) {
  auto paused = driver.stop_if_measuring();
  if (!paused) return paused.error();
  const bool measuring = *paused;
  // BR and UA move the port or the unit: the others are sent and read back first.
  std::vector<Assignment> staying;
  std::vector<Assignment> moving;
  for (const Assignment& assignment : assignments) {
    const std::string_view mnemonic = assignment.target.command->mnemonic;
    (mnemonic == "BR" || mnemonic == "UA" ? moving : staying).push_back(assignment);
  }
  std::vector<Written> accepted;
  const auto keep = [&](const Written& one) {
    accepted.push_back(one);
    if (written) written(one);
  };
  Status done = apply(driver, staying, keep);
  if (done) done = verify(driver, accepted);
  if (done) done = apply(driver, moving, keep);
  // After a UA the unit answers at its new address only.
  for (const Written& one : accepted) {
    if (one.assignment->target.command->mnemonic != "UA" || one.fields.empty()) continue;
    if (const auto moved = parse_unit_address(one.fields.front())) (void)driver.set_address(*moved);
  }
  if (measuring) {
    // Started again even after a refusal: the unit is left measuring, as it was found.
    if (auto started = driver.start_measuring(); !started && done) done = started.error();
  }
  if (!done) return done.error();
  return measuring;
}

}  // namespace rangekit::uls::named
