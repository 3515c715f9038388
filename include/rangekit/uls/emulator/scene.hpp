// What the emulated ULS looks at (docs/emulator-uls.md): targets with
// distance, reflectivity, cooperative flag and motion; dust; ambient noise.
#pragma once
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>
#include "rangekit/core/result.hpp"
#include "rangekit/sim/motion.hpp"

namespace rangekit::uls::emulator {

struct SceneTarget {
  SceneTarget() = default;
  // Brace-initialised in tests and scenes: {name, motion, reflectivity, cooperative}.
  SceneTarget(std::string target_name, Motion target_motion, double target_reflectivity = 0.9,
              bool target_cooperative = false, std::optional<double> width_ns = std::nullopt)
      : name(std::move(target_name)),
        motion(std::move(target_motion)),
        reflectivity(target_reflectivity),
        cooperative(target_cooperative),
        pulse_width_ns(width_ns) {}

  std::string name;
  Motion motion = Motion::fixed(50.0);  // metres from the unit
  double reflectivity = 0.9;            // 0-1 (§9: 90% white, 20% gray)
  bool cooperative = false;             // reflective tape, reflector, prism (§2)
  // Received pulse width in ns; unset: modelled from the signal strength (U40).
  std::optional<double> pulse_width_ns;
};

// The farthest target a scene (file or control socket) may place, in metres.
inline constexpr double max_scene_distance_m = 5000.0;

struct Scene {
  std::vector<SceneTarget> targets;
  double dust = 0.0;           // probability per pulse of a weak return from dust near the unit
  double ambient_noise = 0.5;  // noise hits per pulse, spread over the binning range
};

// One white (90%) target at 50 m, no dust.
Scene default_scene();

// TOML scene; errors name `source` (the file), the line and the key.
Result<Scene> parse_scene(std::string_view toml_text, std::string_view source);
Result<Scene> load_scene(const std::string& path);
// The same fields as a JSON object (control command set_scene).
Result<Scene> scene_from_json(const nlohmann::json& object);

}  // namespace rangekit::uls::emulator
