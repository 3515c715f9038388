#include "cli/uls_values.hpp"

#include <cctype>
#include <cmath>

#include "rangekit/core/text.hpp"
#include "rangekit/uls/formulas.hpp"
#include "rangekit/uls/frame.hpp"
#include "rangekit/uls/host_config.hpp"

namespace rangekit::cli::uls_values {

using namespace rangekit::uls;

namespace {

std::string lower(std::string_view text) {
  std::string out;
  for (const char c : text) out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  return out;
}

// "look down" -> "look-down", "off (polled)" -> "off".
std::string key_name(std::string_view name) {
  std::string text;
  for (const char c : name) {
    if (c == '(') break;
    text.push_back(c == ' ' || c == '_' ? '-' : static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  while (!text.empty() && text.back() == '-') text.pop_back();
  return text;
}

std::optional<std::uint32_t> named_value(const CommandInfo& command, std::string_view typed) {
  const std::string want = key_name(typed);
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
    const std::string name = key_name(entry.name);
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

Result<Target> find_setting(std::string_view name) {
  if (const CommandInfo* command = find_command_by_cli_name(lower(name)); command != nullptr)
    return Target{command, false};
  if (name.size() >= 2 && name.size() <= 4) {
    bool letters = true;
    for (const char c : name) letters = letters && std::isalpha(static_cast<unsigned char>(c)) != 0;
    if (const CommandInfo* command = letters ? find_command(name) : nullptr; command != nullptr)
      return Target{command, true};
  }
  std::string names;
  for (const CommandInfo& command : command_table()) {
    if (command.access == Access::action || command.mnemonic == "BM") continue;
    names += (names.empty() ? "" : ", ") + std::string(command.cli_name);
  }
  return make_error(Errc::unknown_command, "unknown setting '" + std::string(name) + "'; names: " + names +
                                               " (or the 2-letter mnemonics of §8)");
}

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
  for (auto& field : fields) {
    if ((command.kind == ValueKind::flag || command.kind == ValueKind::enumeration) &&
        !text::parse_unsigned(field).has_value()) {
      if (auto number = named_value(command, field)) field = std::to_string(*number);
      // else left as typed: validation names the allowed values
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
      field = std::string(to_hex_text(trip_timeout_pulses(*seconds)).view());
    }
  }
  return fields;
}

std::string describe_reply(const CommandInfo& command, const std::vector<std::string>& values, Units device_units) {
  if (command.mnemonic == "ID") {
    std::string text;
    for (const auto& value : values) text += (text.empty() ? "" : ",") + value;
    return text;
  }
  if (command.mnemonic == "US" && values.size() == 1) {
    const auto number = text::parse_unsigned(values[0]).value_or(0);
    const auto name = command.value_name(static_cast<std::uint32_t>(number));
    return name.empty() ? values[0] : std::string(name);
  }
  if (command.mnemonic == "BR" && values.size() == 2) return values[1] + " baud";
  if (command.mnemonic == "UA" && values.size() == 1) {
    auto address = unit_address_char(text::parse_unsigned(values[0]).value_or(0));
    if (address && *address < 0x7F) return std::string(1, static_cast<char>(*address));
    return values[0];
  }
  if (command.kind == ValueKind::hex_pulses && values.size() == 1) {
    auto pulses = parse_trip_timeout(values[0]);
    if (!pulses) return values[0];
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.1f", trip_timeout_seconds(*pulses));
    return std::string(buffer) + " s (" + std::to_string(*pulses) + " pulses)";
  }
  auto setting = from_wire(command, values, device_units);
  if (!setting) {
    std::string text;
    for (const auto& value : values) text += (text.empty() ? "" : ",") + value;
    return text;
  }
  return readable(*setting);
}

}  // namespace rangekit::cli::uls_values
