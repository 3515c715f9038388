// What the emulated ULS looks at (issue 4, docs/emulator-uls.md): targets with
// distance, reflectivity, cooperative flag and motion; dust; ambient noise.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>
#include "rangekit/core/motion.hpp"
#include "rangekit/core/result.hpp"

namespace rangekit::uls::emulator {

struct SceneTarget {
  std::string name;
  Motion motion = Motion::fixed(50.0);  // metres from the unit
  double reflectivity = 0.9;            // 0-1 (§9: 90% white, 20% gray)
  bool cooperative = false;             // reflective tape, reflector, prism (§2)
};

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
