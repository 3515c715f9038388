// The LS5 model's control socket commands (docs/emulator-ls5.md "Control commands").
#include "rangekit/ls5/emulator/firmware.hpp"

#include <algorithm>
#include <string>

#include "rangekit/sim/control_socket.hpp"

namespace rangekit::ls5::emulator {

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
              {"udp_packets", udp_packets_},
              {"udp_source_port", udp_source_port()},
              {"udp_destination", format_ipv4(udp_destination().ip) + ":" + std::to_string(udp_destination().port)},
              {"udp_unsent", udp_unsent_},
              {"udp_error", udp_error_.empty() ? nlohmann::json() : nlohmann::json(udp_error_)}};
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
