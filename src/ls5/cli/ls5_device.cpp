// `rangekit ls5 info|get|set|latch|measure|start|stop|save|reset` (on, off, defaults: hidden aliases): one request
// (or a few) each, through ls5::Driver; values by readable name or raw address.
#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cli/assignment_file.hpp"
#include "cli/commands.hpp"
#include "cli/key_values.hpp"
#include "ls5/cli/ls5_cli.hpp"
#include "rangekit/core/text.hpp"
#include "rangekit/ls5/parameters.hpp"
#include "rangekit/ls5/settings.hpp"

namespace rangekit::cli {
namespace {

struct DeviceCommand {
  Ls5Connection connection;
  std::vector<std::string> items;  // get: names; set: NAME=VALUE
  std::string from;                // set --from FILE: more NAME=VALUE items
  bool read_only = false;          // latch --read-only
  bool json = false;               // info, get --json
  // What can be checked before the port is opened (set: the names), so a typo costs no wait.
  Status (*check_first)(DeviceCommand& state) = nullptr;
};

// "0B" -> parameter 0B when it is a table 9.2 address.
const ls5::ParameterInfo* raw_parameter(std::string_view text) {
  if (text.size() != 2) return nullptr;
  unsigned value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + 2, value, 16);
  if (error != std::errc{} || end != text.data() + 2) return nullptr;
  return ls5::find_parameter(static_cast<std::uint8_t>(value));
}

// Every setting name get prints; all are writable (table 9.2 lists parameters to write).
std::string setting_names() {
  std::string names;
  for (const ls5::HostSetting& setting : ls5::host_setting_table())
    names += (names.empty() ? "" : ", ") + std::string(setting.name);
  return names;
}

Error unknown_name(std::string_view name) {
  std::vector<std::string> names;
  for (const ls5::HostSetting& setting : ls5::host_setting_table()) names.emplace_back(setting.name);
  if (const auto meant = text::closest(name, names)) {
    return make_error(Errc::unknown_parameter, "'" + std::string(name) + "' is not an LS5 setting; did you mean '" +
                                                   *meant + "'? (`rangekit ls5 set --help` lists every name)");
  }
  return make_error(Errc::unknown_parameter,
                    "'" + std::string(name) +
                        "' is neither an LS5 setting nor a table 9.2 address; names: " + setting_names() +
                        " (or a two-digit address, `rangekit tables "
                        "ls5-parameters`)");
}

// What `info` prints from ID (§9.2): read only, as the ULS's version and status.
constexpr std::array<std::string_view, 5> identification_names{"version", "lower-boundary-mm", "range-mm", "serial",
                                                               "ethernet"};

Error read_only_name(std::string_view name) {
  return make_error(Errc::wrong_form, "'" + std::string(name) +
                                          "' is read-only (the identification); writable names: " + setting_names() +
                                          " (or a two-digit address)");
}

// Numbers as JSON numbers (--json); named values, addresses and hex bytes as text.
void add_setting(KeyValues& out, const ls5::HostSetting& setting, const std::string& text) {
  switch (setting.form) {
    case ls5::SettingForm::byte_number:
    case ls5::SettingForm::value_number:
    case ls5::SettingForm::value_mm:
    case ls5::SettingForm::value_range_mm:
      out.add_number(std::string(setting.name), text);
      return;
    case ls5::SettingForm::byte_named:  // "115200" of baud-rate is a number, "median" is not
      if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos) {
        out.add_number(std::string(setting.name), text);
        return;
      }
      break;
    default:
      break;
  }
  out.add(std::string(setting.name), text);
}

std::string measurement_text(const ls5::Measurement& measurement) {
  switch (measurement.code.kind) {
    case ls5::CodeKind::no_measurement_yet:
      return fmt::format("code={} signal=none_yet", measurement.code.value);
    case ls5::CodeKind::no_signal:
      return fmt::format("code={} signal=lost", measurement.code.value);
    case ls5::CodeKind::result:
      break;
  }
  if (measurement.derivative_mm) {  // §8.9 formula 8.2 (L60)
    return fmt::format("code={} derivative_mm={:.4f} signal=ok", measurement.code.value, *measurement.derivative_mm);
  }
  if (measurement.distance_mm) {
    return fmt::format("code={} distance_mm={:.4f} signal=ok", measurement.code.value, *measurement.distance_mm);
  }
  return fmt::format("code={} signal=ok", measurement.code.value);
}

Status run_info(ls5::Driver& driver, bool json) {
  auto info = driver.info();
  if (!info) return info.error();
  const auto& id = info->identification;
  KeyValues out(json);
  // The names as `get` spells them: kebab case, the unit last (U96).
  out.add_number("address", fmt::format("{}", info->address));
  out.add("version", std::string(id.version_text.view()));
  out.add_number("lower-boundary-mm", fmt::format("{}", id.lower_boundary_mm));
  out.add_number("range-mm", fmt::format("{}", id.range_mm));
  out.add_number("serial", fmt::format("{}", id.serial_number));
  out.add("ethernet", info->ethernet ? "yes" : "no");
  out.finish();
  return ok_status();
}

Status print_all(ls5::Driver& driver, KeyValues& out) {
  auto info = driver.info();  // firmware, range and Ethernet decide what exists
  if (!info) return info.error();
  auto context = driver.context();
  if (!context) return context.error();
  for (const ls5::HostSetting& setting : ls5::host_setting_table()) {
    if (!setting.canonical || !ls5::check_setting_available(setting, context->model)) continue;
    auto reading = driver.get(setting);
    if (!reading) return reading.error();
    add_setting(out, setting, reading->text);
    // The mm form of a code value, from the same bytes.
    const ls5::HostSetting* in_mm = ls5::find_host_setting(std::string(setting.name) + "-mm");
    if (in_mm != nullptr) {
      auto mm = ls5::format_setting(*in_mm, reading->bytes, *context);
      if (mm) add_setting(out, *in_mm, *mm);
    }
  }
  return ok_status();
}

Status run_get(ls5::Driver& driver, const std::vector<std::string>& names, bool json) {
  KeyValues out(json);
  if (names.empty()) {
    Status all = print_all(driver, out);
    if (all) out.finish();
    return all;
  }
  for (const std::string& name : names) {
    if (const ls5::ParameterInfo* parameter = raw_parameter(name)) {
      auto value = driver.read_parameter(parameter->address);
      if (!value) return value.error();
      out.add(ls5::hex_byte(parameter->address), ls5::hex_byte(*value));
      continue;
    }
    const ls5::HostSetting* setting = ls5::find_host_setting(name);
    if (setting == nullptr) return unknown_name(name);
    auto reading = driver.get(*setting);
    if (!reading) return reading.error();
    add_setting(out, *setting, reading->text);
  }
  out.finish();
  return ok_status();
}

bool is_broadcast(const ls5::Driver& driver) { return driver.address() == ls5::broadcast_address; }

// Table 9.1 note 2: nothing answers a broadcast, so nothing confirms it either.
void note_broadcast(const ls5::Driver& driver) {
  if (is_broadcast(driver)) {
    fmt::print(stderr, "note: sent to every sensor (address 0); broadcasts are not answered (table 9.1 note 2)\n");
  }
}

// Each NAME of NAME=VALUE is a setting or a table 9.2 address; the values need the sensor's
// range and model, so run_set checks them once it is open.
// Why `set` refuses a name that is no writable setting: read-only, or unknown.
Error not_settable(std::string_view name) {
  for (const std::string_view read_only : identification_names)
    if (name == read_only) return read_only_name(name);
  return unknown_name(name);
}

Status check_set_names(DeviceCommand& state) {
  if (!state.from.empty()) {
    auto lines = read_assignments(state.from);
    if (!lines) return lines.error();
    state.items.insert(state.items.begin(), lines->begin(), lines->end());
  }
  if (state.items.empty()) {
    return make_error(Errc::wrong_form, "give NAME=VALUE (e.g. median-points=5, 0B=01) or --from FILE");
  }
  for (const std::string& item : state.items) {
    const std::string name = item.substr(0, item.find('='));
    if (raw_parameter(name) == nullptr && ls5::find_host_setting(name) == nullptr) return not_settable(name);
  }
  return ok_status();
}

// Every item is parsed and checked before the first byte goes out: raw bytes first, as
// one batch whose combined values the driver checks (reading what it needs) before it
// writes any (L61), then named settings, then link settings (L28).
Status run_set(ls5::Driver& driver, const std::vector<std::string>& items) {
  struct Planned {
    std::string name, value;
    const ls5::ParameterInfo* raw = nullptr;
    std::uint8_t raw_value = 0;
    bool link = false;  // address, baud or byte format: the next request needs new --baud/--address
  };
  std::vector<Planned> plan;
  auto context = driver.context();
  if (!context) return context.error();
  for (const std::string& item : items) {
    const std::size_t equals = item.find('=');
    if (equals == std::string::npos) {
      return make_error(Errc::wrong_form, "'" + item + "' is not NAME=VALUE (e.g. median-points=5, 0B=01)");
    }
    Planned planned{item.substr(0, equals), item.substr(equals + 1)};
    if ((planned.raw = raw_parameter(planned.name)) != nullptr) {
      unsigned byte = 0;
      const auto [end, error] =
          std::from_chars(planned.value.data(), planned.value.data() + planned.value.size(), byte, 16);
      if (planned.value.empty() || planned.value.size() > 2 || error != std::errc{} ||
          end != planned.value.data() + planned.value.size()) {
        return make_error(Errc::bad_hex, item + ": a raw parameter value is two hex digits (e.g. 0B=01)");
      }
      planned.raw_value = static_cast<std::uint8_t>(byte);
      ls5::SensorModel model = context->model;
      model.ethernet = model.ethernet || model.firmware.at_least(ls5::firmware_12_x);
      Status accepted = ls5::check_parameter_byte(planned.raw->address, planned.raw_value, model);
      if (!accepted) return accepted.error();
      const ls5::HostSetting* owner = ls5::host_setting_for_parameter(planned.raw->address);
      planned.link = owner != nullptr && owner->link;
    } else {
      const ls5::HostSetting* setting = ls5::find_host_setting(planned.name);
      if (setting == nullptr) return not_settable(planned.name);
      auto writes = ls5::encode_setting(*setting, planned.value, *context);
      if (!writes) return writes.error();
      planned.link = setting->link;
    }
    plan.push_back(std::move(planned));
  }
  // A write to 01/04/05 takes effect after its echo (L28): the settings after it
  // would go out at the old speed or address, so link settings are written last.
  std::stable_partition(plan.begin(), plan.end(), [](const Planned& planned) { return !planned.link; });
  std::stable_partition(plan.begin(), plan.end(),
                        [](const Planned& planned) { return planned.raw != nullptr && !planned.link; });
  std::vector<ls5::ParameterWrite> raw_bytes;
  for (const Planned& planned : plan) {
    if (planned.raw != nullptr && !planned.link) raw_bytes.push_back({planned.raw->address, planned.raw_value});
  }
  if (!raw_bytes.empty()) {
    Status written = driver.write_parameters(raw_bytes);
    if (!written) return written.error();
  }
  for (const Planned& planned : plan) {
    if (planned.raw == nullptr || planned.link) {
      Status written = planned.raw != nullptr ? driver.write_parameter(planned.raw->address, planned.raw_value)
                                              : driver.set(planned.name, planned.value);
      if (!written) return written.error();
    }
    fmt::print("{}={}\n", planned.name, planned.value);
    if (planned.link) {
      fmt::print(stderr,
                 "note: {} applies from the next request: talk to the sensor with the new --baud or --address "
                 "(`save` keeps it over a power cycle)\n",
                 planned.name);
    }
  }
  note_broadcast(driver);
  return ok_status();
}

using Action = std::function<Status(ls5::Driver&, DeviceCommand&)>;

// Whether the command may go to address 0: only table 9.1 note 1 commands, which need no answer.
enum class Broadcast : bool { refused, allowed };

CLI::App* add_device_command(CLI::App& ls5, int& exit_code, const std::string& name, const std::string& help,
                             const Action& action, std::shared_ptr<DeviceCommand> state = nullptr,
                             Broadcast broadcast = Broadcast::refused) {
  if (!state) state = std::make_shared<DeviceCommand>();
  auto* command = ls5.add_subcommand(name, help);
  add_ls5_connection_options(*command, state->connection);
  command->callback([&exit_code, state, action, name, broadcast] {
    if (state->check_first != nullptr) {
      if (Status checked = state->check_first(*state); !checked) {
        exit_code = report_ls5_failure(name, checked.error(), state->connection);
        return;
      }
    }
    auto driver = open_ls5_driver(state->connection, broadcast == Broadcast::allowed);
    if (!driver) {
      exit_code = report_ls5_failure(name, driver.error(), state->connection);
      return;
    }
    Status done = action(**driver, *state);
    exit_code = done ? exit_ok : report_ls5_failure(name, done.error(), state->connection);
  });
  return command;
}

Status echo_done(const ls5::Driver& driver, Status status, std::string_view what) {
  if (status) {
    fmt::print("{}\n", what);
    note_broadcast(driver);
  }
  return status;
}

}  // namespace

void add_ls5_device_commands(CLI::App& ls5, int& exit_code) {
  auto info_state = std::make_shared<DeviceCommand>();
  auto* info = add_device_command(
      ls5, exit_code, "info", "identification (ID): version, lower boundary, range, serial",
      [](ls5::Driver& driver, DeviceCommand& state) { return run_info(driver, state.json); }, info_state);
  info->add_flag("--json", info_state->json, "one JSON object instead of NAME=VALUE lines");

  auto get_state = std::make_shared<DeviceCommand>();
  auto* get = add_device_command(
      ls5, exit_code, "get", "read settings by name (median-points, period-ms, ...) or address (0B); all without names",
      [](ls5::Driver& driver, DeviceCommand& state) { return run_get(driver, state.items, state.json); }, get_state);
  get->add_flag("--json", get_state->json, "one JSON object instead of NAME=VALUE lines");
  get->add_option("names", get_state->items, "setting names or two-digit parameter addresses");

  auto set_state = std::make_shared<DeviceCommand>();
  set_state->check_first = check_set_names;
  auto* set = add_device_command(
      ls5, exit_code, "set", "write settings NAME=VALUE (median-points=5, analog-lower-mm=12.5, 0B=01), checked first",
      [](ls5::Driver& driver, DeviceCommand& state) { return run_set(driver, state.items); }, set_state,
      Broadcast::allowed);
  set->add_option("settings", set_state->items, "NAME=VALUE or AA=DD (hex)");
  add_from_option(*set, set_state->from);
  set->footer("Writable names (as `get` prints them): " + setting_names());

  auto latch_state = std::make_shared<DeviceCommand>();
  auto* latch = add_device_command(
      ls5, exit_code, "latch", "latch the current result (FX) and read it back (FR)",
      [](ls5::Driver& driver, DeviceCommand& state) -> Status {
        if (is_broadcast(driver)) {  // FX to every sensor; FR would need an answer
          if (state.read_only) {
            return make_error(Errc::wrong_form,
                              "--read-only reads the latched result (FR), which needs an answer: a broadcast "
                              "(address 0) gets none (table 9.1 note 2)");
          }
          return echo_done(driver, driver.latch(), "latched (FX); read each sensor's result with `latch --read-only`");
        }
        auto identified = driver.identify();  // the range turns the code into mm
        if (!identified) return identified.error();
        if (!state.read_only) {
          Status latched = driver.latch();
          if (!latched) return latched;
        }
        auto result = driver.read_latched();
        if (!result) return result.error();
        fmt::print("{}\n", measurement_text(*result));
        return ok_status();
      },
      latch_state, Broadcast::allowed);
  latch->add_flag("--read-only", latch_state->read_only, "only read the latched result (FR), do not latch");

  add_device_command(ls5, exit_code, "measure", "read the last result (LR)",
                     [](ls5::Driver& driver, DeviceCommand&) -> Status {
                       auto identified = driver.identify();
                       if (!identified) return identified.error();
                       auto result = driver.measure();
                       if (!result) return result.error();
                       fmt::print("{}\n", measurement_text(*result));
                       return ok_status();
                     });
  // The same verbs as `rangekit uls` (docs/cli.md): start, stop, reset. The LS5's own
  // words (on, off, defaults) stay as hidden aliases so that scripts keep working.
  for (const auto& [name, hidden] : {std::pair{"start", false}, std::pair{"on", true}}) {
    auto* start = add_device_command(
        ls5, exit_code, name, "turn the sensor on (ON): laser and measurements",
        [](ls5::Driver& driver, DeviceCommand&) { return echo_done(driver, driver.start_measuring(), "measuring"); },
        nullptr, Broadcast::allowed);
    if (hidden) start->group("");
  }
  for (const auto& [name, hidden] : {std::pair{"stop", false}, std::pair{"off", true}}) {
    auto* stop = add_device_command(
        ls5, exit_code, name, "turn the sensor off (OF): no measurements",
        [](ls5::Driver& driver, DeviceCommand&) { return echo_done(driver, driver.stop_measuring(), "stopped"); },
        nullptr, Broadcast::allowed);
    if (hidden) stop->group("");
  }
  add_device_command(
      ls5, exit_code, "save", "store the current parameters to non-volatile memory (FL)",
      [](ls5::Driver& driver, DeviceCommand&) { return echo_done(driver, driver.store_to_flash(), "saved"); }, nullptr,
      Broadcast::allowed);
  for (const auto& [name, hidden] : {std::pair{"reset", false}, std::pair{"defaults", true}}) {
    auto* reset = add_device_command(
        ls5, exit_code, name, "restore the table 9.2 defaults in RAM (DF); `save` keeps them over a power cycle",
        [](ls5::Driver& driver, DeviceCommand&) {
          const std::uint8_t was_at = driver.address();
          Status restored = echo_done(driver, driver.restore_defaults(), "defaults restored (RAM only until `save`)");
          if (restored && was_at != ls5::broadcast_address && was_at != ls5::default_network_address) {
            fmt::print("the sensor now answers at address {} (table 9.2 default); it was {}\n",
                       ls5::default_network_address, was_at);
          }
          return restored;
        },
        nullptr, Broadcast::allowed);
    if (hidden) reset->group("");
  }
}

}  // namespace rangekit::cli
