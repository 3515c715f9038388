// `rangekit sim uls`: the ULS emulator (docs/emulator-uls.md). One unit
// with its universal and configuration ports, or up to 64 units on one RS-485 bus.
#include <fmt/core.h>

#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "cli/sim.hpp"
#include "rangekit/uls/emulator/firmware.hpp"
#include "uls/cli/uls_cli.hpp"

namespace rangekit::cli {
namespace {

using uls::emulator::Firmware;
using uls::emulator::FirmwareOptions;

struct SimUlsOptions {
  SimCommonOptions common;
  std::string port;         // universal port symlink
  std::string config_port;  // configuration port symlink
  std::string bus;          // RS-485 bus symlink
  std::vector<std::string> addresses;
  double turnaround_ms = 1.0;
};

// "Z", "0x5A" or "unassigned" (factory address 0, U3).
std::optional<std::uint8_t> parse_address(const std::string& text, bool& unassigned) {
  unassigned = text == "unassigned" || text == "none";
  if (unassigned) return std::uint8_t{0};
  unsigned value = 0;
  if (text.size() == 1) {
    value = static_cast<unsigned char>(text[0]);
  } else if (text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
    try {
      value = static_cast<unsigned>(std::stoul(text.substr(2), nullptr, 16));
    } catch (const std::exception&) {
      return std::nullopt;
    }
  } else {
    return std::nullopt;
  }
  if (value < uls::first_unit_address || value > uls::last_unit_address) return std::nullopt;
  return static_cast<std::uint8_t>(value);
}

// Device commands of the control socket, routed by "device": index or address character.
nlohmann::json handle_device_command(const std::vector<std::unique_ptr<Firmware>>& units, const nlohmann::json& request,
                                     Nanos now) {
  static constexpr std::array<std::string_view, 6> commands{"outputs", "set_scene",       "move_target",
                                                            "fault",   "min_pulse_width", "power_cycle"};
  const std::string command = request.value("cmd", "");
  if (std::find(commands.begin(), commands.end(), command) == commands.end()) return nullptr;
  std::vector<Firmware*> chosen;
  if (request.contains("device")) {
    const auto& device = request.at("device");
    if (device.is_number_unsigned()) {
      const auto index = device.get<std::size_t>();
      if (index >= units.size()) return {{"error", fmt::format("{}: no device {}", command, index)}};
      chosen.push_back(units[index].get());
    } else if (device.is_string() && device.get<std::string>().size() == 1) {
      const auto address = static_cast<std::uint8_t>(device.get<std::string>()[0]);
      for (const auto& unit : units) {
        if (unit->settings().address == address) chosen.push_back(unit.get());
      }
      if (chosen.empty())
        return {{"error", fmt::format("{}: no device with address '{}'", command, device.get<std::string>())}};
    } else {
      return {{"error", command + ": 'device' is an index or an address character"}};
    }
  } else {
    for (const auto& unit : units) chosen.push_back(unit.get());
  }
  // Each unit acts at the runtime's present (`now`), not at the last time it ran.
  if (chosen.size() == 1) return chosen.front()->control(request, now);
  nlohmann::json replies = nlohmann::json::array();
  for (auto* unit : chosen) replies.push_back(unit->control(request, now));
  return {{"ok", true}, {"devices", replies}};
}

int run(const SimUlsOptions& options) {
  if (!options.bus.empty() && (!options.port.empty() || !options.config_port.empty())) {
    fmt::print(stderr, "rangekit sim uls: --bus runs units on one RS-485 line; it does not combine with --port\n");
    return exit_usage;
  }
  if (options.bus.empty() && !options.addresses.empty() && options.addresses.size() > 1) {
    fmt::print(stderr, "rangekit sim uls: several --address need --bus\n");
    return exit_usage;
  }
  if (options.addresses.size() > 64) {
    fmt::print(stderr, "rangekit sim uls: at most 64 units on one bus\n");
    return exit_usage;
  }
  uls::emulator::Scene scene = uls::emulator::default_scene();
  if (!options.common.scene.empty()) {
    auto loaded = uls::emulator::load_scene(options.common.scene);
    if (!loaded) {
      fmt::print(stderr, "rangekit sim uls: {}\n", loaded.error().message);
      return scene_exit_code(loaded.error());
    }
    scene = std::move(*loaded);
  }
  std::vector<std::unique_ptr<Firmware>> units;
  auto make_unit = [&](std::optional<std::uint8_t> address, std::string key, std::uint32_t seed) {
    FirmwareOptions unit_options;
    unit_options.state_dir = options.common.state_dir;
    unit_options.state_key = std::move(key);
    unit_options.seed = seed;
    unit_options.address = address;
    unit_options.scene = scene;
    unit_options.turnaround =
        std::chrono::duration_cast<Nanos>(std::chrono::duration<double, std::milli>(options.turnaround_ms));
    units.push_back(std::make_unique<Firmware>(std::move(unit_options)));
  };
  std::vector<LineConfig> lines;
  if (!options.bus.empty()) {
    if (options.addresses.empty()) {
      fmt::print(stderr, "rangekit sim uls: --bus needs at least one --address\n");
      return exit_usage;
    }
    LineConfig bus{"bus", options.bus, {}};
    for (std::size_t i = 0; i < options.addresses.size(); ++i) {
      bool unassigned = false;
      const auto address = parse_address(options.addresses[i], unassigned);
      if (!address) {
        fmt::print(stderr,
                   "rangekit sim uls: --address '{}' is not a unit address (one character 0x30-0xEF, 0xNN, or "
                   "'unassigned')\n",
                   options.addresses[i]);
        return exit_usage;
      }
      make_unit(unassigned ? std::nullopt : address, fmt::format("uls-bus-{}", i),
                options.common.seed + static_cast<std::uint32_t>(i));
    }
    for (const auto& unit : units) bus.attachments.push_back(LineAttachment{unit.get(), uls::emulator::universal_port});
    lines.push_back(std::move(bus));
  } else {
    std::optional<std::uint8_t> address;
    if (!options.addresses.empty()) {
      bool unassigned = false;
      address = parse_address(options.addresses[0], unassigned);
      if (!address) {
        fmt::print(stderr, "rangekit sim uls: --address '{}' is not a unit address\n", options.addresses[0]);
        return exit_usage;
      }
      if (unassigned) address.reset();
    }
    make_unit(address, "uls", options.common.seed);
    auto link = [](const std::string& path) { return path.empty() ? std::nullopt : std::optional<std::string>(path); };
    lines.push_back(
        LineConfig{"universal", link(options.port), {LineAttachment{units[0].get(), uls::emulator::universal_port}}});
    lines.push_back(LineConfig{"configuration",
                               link(options.config_port),
                               {LineAttachment{units[0].get(), uls::emulator::configuration_port}}});
  }
  return run_emulator(
      std::move(lines), options.common, "rangekit sim uls",
      [&units](const nlohmann::json& request, Nanos now) { return handle_device_command(units, request, now); });
}

}  // namespace

void add_sim_uls(CLI::App& sim, int& exit_code) {
  auto options = std::make_shared<SimUlsOptions>();
  auto* command = sim.add_subcommand("uls", "ULS emulator: the universal and configuration ports, or an RS-485 bus");
  command->add_option("--port", options->port, "symlink to the universal port's pty (RS-232/RS-485, 12-pin)");
  command->add_option("--config-port", options->config_port, "symlink to the configuration port's pty (4-pin)");
  command->add_option("--bus", options->bus, "symlink to one RS-485 pty shared by the --address units");
  command->add_option("--address", options->addresses,
                      "unit address: one character 0x30-0xEF, 0xNN, or 'unassigned' (repeat for a --bus)");
  command
      ->add_option("--turnaround-ms", options->turnaround_ms,
                   "from a request's last byte to the reply's first (default 1; the document states none)")
      ->check(CLI::Range(0.0, 100.0));
  add_common_sim_options(*command, options->common);
  command->callback([options, &exit_code] { exit_code = run(*options); });
}

}  // namespace rangekit::cli
