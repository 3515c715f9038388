// Config files: every setting of a unit as readable TOML (the Interface
// Program's .uls file, §2), loading with read-back verification, and diff.
#include "rangekit/uls/host_config.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/toml.hpp"  // private: toml++ is no part of the public API
#include "rangekit/core/text.hpp"
#include "rangekit/uls/describe.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/formulas.hpp"
#include "rangekit/uls/named_settings.hpp"

namespace rangekit::uls {

namespace {

std::string integer_text(double value) { return std::to_string(static_cast<std::uint64_t>(std::llround(value))); }

std::string unit_comment(const CommandInfo& command) {
  std::string text = "# " + std::string(command.mnemonic) + ", " + std::string(command.title);
  if (command.is_distance())
    text += ", metres";
  else if (command.kind == ValueKind::hex_pulses)
    text += ", seconds (the unit counts 3000 pulses a second)";
  else if (!command.unit.empty())
    text += ", " + std::string(command.unit);
  if (!command.value_names.empty() && command.kind == ValueKind::enumeration) {
    text += ":";
    for (const auto& entry : command.value_names) text += " " + value_key(entry.name);
  }
  return text;
}

Error toml_error(std::string_view file, std::size_t line, std::string_view key, std::string_view what) {
  return make_error(Errc::bad_number, std::string(file) + ":" + std::to_string(line) + ": '" + text::printable(key) +
                                          "' " + std::string(what));
}

}  // namespace

std::vector<const CommandInfo*> config_commands() {
  std::vector<const CommandInfo*> list{find_command("MU")};
  for (const CommandInfo& command : command_table()) {
    if (command.access != Access::get_set) continue;
    if (command.mnemonic == "MU" || command.mnemonic == "BR" || command.mnemonic == "UA") continue;
    list.push_back(&command);
  }
  return list;
}

std::vector<std::string> to_wire(const Setting& setting, Units units) {
  std::vector<std::string> wire;
  for (const double value : setting.values) {
    switch (setting.command->kind) {
      case ValueKind::distance:
      case ValueKind::signed_distance: {
        auto text = format_distance(from_metres(value, units), units);
        wire.emplace_back(text ? std::string(text->view()) : "nan");
        break;
      }
      case ValueKind::milliamps:
      case ValueKind::seconds:
        wire.push_back(decimal_text(value));
        break;
      case ValueKind::hex_pulses:
        wire.emplace_back(to_hex_text(static_cast<std::uint64_t>(std::llround(value))).view());
        break;
      default:
        wire.push_back(integer_text(value));
    }
  }
  return wire;
}

Result<Setting> from_wire(const CommandInfo& command, const std::vector<std::string>& values, Units units) {
  Setting setting;
  setting.command = &command;
  for (const auto& text : values) {
    std::optional<double> value;
    if (command.is_distance()) {
      // A limit read in feet is that limit (U76): 5577.43 ft -> 1700 m, not 1700.0007.
      if (auto number = text::parse_decimal(text)) value = distance_to_metres(*number, units, command.min, command.max);
    } else if (command.kind == ValueKind::milliamps || command.kind == ValueKind::seconds) {
      value = text::parse_decimal(text);
    } else if (command.kind == ValueKind::hex_pulses) {
      if (auto pulses = parse_trip_timeout(text)) value = static_cast<double>(*pulses);
    } else if (auto number = text::parse_unsigned(text)) {
      value = static_cast<double>(*number);
    }
    if (!value)
      return make_error(Errc::invalid_frame,
                        "$" + std::string(command.mnemonic) + " value '" + text + "' does not read");
    setting.values.push_back(*value);
  }
  return setting;
}

std::string readable(const Setting& setting) {
  const CommandInfo& command = *setting.command;
  std::string text;
  for (const double value : setting.values) {
    if (!text.empty()) text += ",";
    if (command.kind == ValueKind::flag) {
      text += value != 0 ? "on" : "off";
    } else if (command.kind == ValueKind::enumeration) {
      const auto name = command.value_name(static_cast<std::uint32_t>(value));
      text += name.empty() ? integer_text(value) : value_key(name);
    } else if (command.is_distance() || command.kind == ValueKind::milliamps || command.kind == ValueKind::seconds) {
      text += decimal_text(value);
    } else {
      text += integer_text(value);
    }
  }
  if (command.is_distance())
    text += " m";
  else if (command.kind == ValueKind::milliamps)
    text += " mA";
  else if (command.kind == ValueKind::seconds)
    text += " s";
  else if (command.kind == ValueKind::prf_list)
    text += " Hz";
  else if (command.kind == ValueKind::hex_pulses)
    text += " pulses";
  return text;
}

Result<DeviceConfig> read_config(Driver& driver) {
  DeviceConfig config;
  auto version = driver.version();
  if (!version) return version.error();
  config.version = *version;
  auto units = driver.units();
  if (!units) return units.error();
  for (const CommandInfo* command : config_commands()) {
    auto values = driver.get(command->mnemonic);
    if (!values) return values.error();
    auto setting = from_wire(*command, *values, *units);
    if (!setting) return setting.error();
    config.settings.push_back(std::move(*setting));
  }
  return config;
}

std::string config_to_toml(const DeviceConfig& config, std::string_view origin) {
  std::ostringstream out;
  out << "# ULS settings, saved by rangekit (the Interface Program's .uls file as TOML).\n";
  out << "# " << origin << "\n";
  if (!config.version.empty()) out << "# unit: " << config.version << "\n";
  out << "# Names and values are those of `rangekit uls get`, which `set` takes too; each\n";
  out << "# comment gives the mnemonic. Load with `rangekit uls config load FILE`.\n\n";
  out << "[settings]\n";
  for (const Setting& setting : config.settings) {
    const CommandInfo& command = *setting.command;
    const std::string text = named::without_unit(command, readable(setting));
    std::string value;
    if (command.kind == ValueKind::flag || command.kind == ValueKind::enumeration) {
      value = "\"" + text + "\"";
    } else if (command.kind == ValueKind::prf_list || command.kind == ValueKind::ppm_list) {
      value = "[" + text + "]";
      for (std::size_t comma = value.find(','); comma != std::string::npos; comma = value.find(',', comma + 2))
        value.insert(comma + 1, " ");
    } else if (command.kind == ValueKind::unsigned_int) {
      value = text;
    } else {
      // A float in TOML, so that a distance or a time reads as one.
      value = text;
      if (value.find('.') == std::string::npos) value += ".0";
    }
    out << named::setting_key(command) << " = " << value << "  " << unit_comment(command) << "\n";
  }
  return out.str();
}

namespace {

// A TOML value as `set` would take it typed: "on", "binning", "10.5", "2000,2000,2000".
std::optional<std::string> typed_value(const toml::node& node) {
  if (auto flag = node.value_exact<bool>()) return std::string(*flag ? "on" : "off");
  if (auto text = node.value_exact<std::string>()) return *text;
  if (auto integer = node.value_exact<std::int64_t>()) return std::to_string(*integer);
  if (auto number = node.value_exact<double>()) {
    std::array<char, 32> buffer{};  // the shortest text that reads back as the same double
    const auto end = std::to_chars(buffer.data(), buffer.data() + buffer.size(), *number).ptr;
    return std::string(buffer.data(), end);
  }
  if (const toml::array* array = node.as_array()) {
    std::string joined;
    for (const auto& element : *array) {
      if (element.is_array() || element.is_table()) return std::nullopt;
      auto one = typed_value(element);
      if (!one) return std::nullopt;
      joined += (joined.empty() ? "" : ",") + *one;
    }
    return joined;
  }
  return std::nullopt;
}

// The setting a key names, as `get` names it; the reasons a key is not one, said.
Result<const CommandInfo*> config_setting(std::string_view key, const std::vector<const CommandInfo*>& kept) {
  auto target = named::find_setting(key, named::Purpose::get);
  if (!target) {
    const std::string& message = target.error().message;
    const auto meant = message.find("; did you mean");
    return make_error(Errc::unknown_command,
                      "is not a ULS setting" + (meant == std::string::npos ? std::string(" (see `rangekit uls get`)")
                                                                           : message.substr(meant)));
  }
  const CommandInfo* command = target->command;
  if (target->raw)
    return make_error(Errc::unknown_command, "is a mnemonic: a config file names it as `rangekit uls get` does, " +
                                                 named::setting_key(*command));
  if (std::find(kept.begin(), kept.end(), command) == kept.end())
    return make_error(Errc::unknown_command,
                      "is not kept in a config file (the baud rate and the address would "
                      "cut the link; the others are only read)");
  // The earlier name of TT counted pulses in saved files and seconds on the command line.
  if (command->kind == ValueKind::hex_pulses && key != named::setting_key(*command))
    return make_error(Errc::unknown_command,
                      "names no unit: write " + named::setting_key(*command) + " in seconds (pulses / 3000)");
  return command;
}

}  // namespace

Result<DeviceConfig> config_from_toml(std::string_view text, std::string_view file_name) {
  auto parsed = parse_toml(text, file_name);
  if (!parsed) return std::move(parsed).error();
  toml::table& root = *parsed;
  const toml::table* table = root["settings"].as_table();
  if (table == nullptr) return make_error(Errc::invalid_frame, std::string(file_name) + ": no [settings] table");
  DeviceConfig config;
  const auto commands = config_commands();
  for (const auto& [key, node] : *table) {
    const std::size_t line = node.source().begin.line;
    auto command = config_setting(key.str(), commands);
    if (!command) return toml_error(file_name, line, key.str(), command.error().message);
    auto typed = typed_value(node);
    if (!typed) return toml_error(file_name, line, key.str(), "must be a number, a name or a list of numbers");
    // The same reading as `set`: distances in metres, trip-timeout-s in seconds.
    const named::Target target{*command, false, ""};
    auto fields = named::to_fields(target, *typed, Units::metres);
    if (!fields) {
      // set's refusal without its leading name, which the file's message gives, and without
      // the mnemonic form, which a file does not take.
      std::string message = fields.error().message;
      const std::string named = std::string((*command)->cli_name) + ": ";
      if (message.rfind(named, 0) == 0) message.erase(0, named.size());
      if (const auto raw = message.find(", or the code as "); raw != std::string::npos) message.resize(raw);
      return toml_error(file_name, line, key.str(), message);
    }
    const std::vector<std::string_view> views(fields->begin(), fields->end());
    if (const Verdict verdict = validate_request(**command, views, Units::metres); !verdict.ok()) {
      const bool named_values = (*command)->kind == ValueKind::enumeration || (*command)->kind == ValueKind::flag;
      return toml_error(file_name, line, key.str(),
                        (named_values ? "must be one of: " : "is outside the allowed values: ") +
                            allowed_values(**command, Units::metres));
    }
    auto setting = from_wire(**command, *fields, Units::metres);
    if (!setting) return toml_error(file_name, line, key.str(), "does not read: " + *typed);
    config.settings.push_back(std::move(*setting));
  }
  // Keep the order config_commands() gives (MU first).
  DeviceConfig ordered;
  for (const CommandInfo* command : commands)
    for (auto& setting : config.settings)
      if (setting.command == command) ordered.settings.push_back(std::move(setting));
  return ordered;
}

std::vector<ConfigDifference> diff_config(const DeviceConfig& wanted, const DeviceConfig& actual) {
  std::vector<ConfigDifference> differences;
  for (const Setting& want : wanted.settings) {
    for (const Setting& have : actual.settings) {
      if (have.command != want.command) continue;
      // Compared as the unit would send them, in metres (3 decimals).
      if (to_wire(want, Units::metres) != to_wire(have, Units::metres))
        differences.push_back({want.command, readable(want), readable(have)});
    }
  }
  return differences;
}

Result<LoadReport> load_config(Driver& driver, const DeviceConfig& config) {
  auto paused = driver.stop_if_measuring();
  if (!paused) return paused.error();
  const bool was_measuring = *paused;
  LoadReport report;
  std::vector<const Setting*> later;
  Units units = Units::metres;
  for (const Setting& setting : config.settings) {
    if (setting.command->mnemonic == "MU") units = static_cast<Units>(static_cast<std::uint8_t>(setting.values.at(0)));
  }
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<const Setting*> list;
    if (pass == 0) {
      for (const Setting& setting : config.settings) list.push_back(&setting);
    } else {
      list = later;
    }
    for (const Setting* setting : list) {
      const auto wire = to_wire(*setting, setting->command->mnemonic == "MU" ? Units::metres : units);
      const std::vector<std::string_view> fields(wire.begin(), wire.end());
      auto sent = driver.set(setting->command->mnemonic, fields);
      ++report.sent;
      if (sent) continue;
      const int code = sent.error().device_code;
      // Order rules: PPM must exceed AW (49), the 4 mA and 20 mA ranges must differ (83).
      if (pass == 0 &&
          (code == error_number::ppo_not_greater_than_weight || code == error_number::invalid_current_loop_range)) {
        later.push_back(setting);
        continue;
      }
      return sent.error();
    }
  }
  auto back = read_config(driver);
  if (!back) return back.error();
  report.mismatches = diff_config(config, *back);
  if (was_measuring) {
    if (auto started = driver.start_measuring(); !started) return started.error();
  }
  return report;
}

DeviceConfig factory_config() {
  // U35: the emulator's factory settings, read off the §2 screenshots.
  const std::vector<std::pair<std::string_view, std::vector<double>>> values{
      {"MU", {1}},          {"DD", {0}},
      {"MA", {0}},          {"PA", {0}},
      {"CL", {0}},          {"AW", {992}},
      {"BS", {0}},          {"BH", {128}},
      {"CO", {1}},          {"FL", {0}},
      {"DM", {2}},          {"AF", {3.0}},
      {"AT", {0}},          {"LG", {0}},
      {"MM", {1}},          {"MO", {0}},
      {"PL", {0}},          {"PF", {2000, 2000, 2000}},
      {"PO", {1024, 1024}}, {"AH", {10}},
      {"AL", {0}},          {"TE", {0}},
      {"SG", {0}},          {"TB", {0}},
      {"TP", {0.2}},        {"TT", {static_cast<double>(rereference_pulses)}},
      {"OF", {0}}};
  DeviceConfig config;
  for (const CommandInfo* command : config_commands())
    for (const auto& [mnemonic, numbers] : values)
      if (command->mnemonic == mnemonic) config.settings.push_back(Setting{command, numbers});
  return config;
}

}  // namespace rangekit::uls
