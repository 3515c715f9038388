// Scene files for the ULS emulator (TOML, docs/emulator-uls.md "Scene").
#include "rangekit/uls/emulator/scene.hpp"

#include <fstream>
#include <sstream>

#include "sim/scene_toml.hpp"

namespace rangekit::uls::emulator {
namespace {

constexpr double max_distance_m = max_scene_distance_m;

// Keys are quoted in messages: "s.toml:2: 'distnce_m': unknown key" (docs/emulator-uls.md).
std::string where(std::string_view source, const toml::node& node, std::string_view key) {
  return sim::where(source, node, key, sim::KeyStyle::quoted);
}

Result<double> toml_number(std::string_view source, const toml::table& table, std::string_view key, double fallback,
                           double min, double max) {
  return sim::number(source, table, key, fallback, min, max, sim::KeyStyle::quoted);
}

Status check_keys(std::string_view source, const toml::table& table, std::initializer_list<std::string_view> known,
                  std::string_view section) {
  return sim::check_keys(source, table, known, section, sim::KeyStyle::quoted);
}

Result<SceneTarget> toml_target(std::string_view source, const toml::table& table, std::size_t index) {
  const std::string section = "[[targets]] #" + std::to_string(index + 1);
  if (auto keys = check_keys(
          source, table,
          {"name", "distance_m", "reflectivity", "cooperative", "pulse_width_ns", "speed_mps", "path", "repeat"},
          section);
      !keys)
    return keys.error();
  SceneTarget target;
  target.name = table["name"].value_or(std::string("target ") + std::to_string(index + 1));
  auto reflectivity = toml_number(source, table, "reflectivity", 0.9, 0.0, 1.0);
  if (!reflectivity) return reflectivity.error();
  target.reflectivity = *reflectivity;
  if (const toml::node* node = table.get("cooperative")) {
    const auto flag = node->value<bool>();
    if (!flag) return make_error(Errc::invalid_frame, where(source, *node, "cooperative") + " must be true or false");
    target.cooperative = *flag;
  }
  if (table.get("pulse_width_ns") != nullptr) {
    // §9: the width field is at most 7 digits of picoseconds (U40).
    auto width = toml_number(source, table, "pulse_width_ns", 0.0, 0.001, 9999.999);
    if (!width) return width.error();
    target.pulse_width_ns = *width;
  }
  if (const toml::node* path_node = table.get("path")) {
    const toml::array* points = path_node->as_array();
    if (points == nullptr || points->empty())
      return make_error(Errc::invalid_frame,
                        where(source, *path_node, "path") + " must be an array of [time_s, distance_m] pairs");
    std::vector<PathPoint> path;
    for (const auto& point : *points) {
      const toml::array* pair = point.as_array();
      const auto t = pair && pair->size() == 2 ? (*pair)[0].value<double>() : std::nullopt;
      const auto d = pair && pair->size() == 2 ? (*pair)[1].value<double>() : std::nullopt;
      if (!t || !d)
        return make_error(Errc::invalid_frame,
                          where(source, point, "path") + " points are [time_s, distance_m] pairs of numbers");
      path.push_back(PathPoint{*t, *d});
    }
    auto motion = Motion::path(std::move(path), table["repeat"].value_or(false));
    if (!motion)
      return make_error(Errc::invalid_frame, where(source, *path_node, "path") + ": " + motion.error().message);
    target.motion = std::move(*motion);
    return target;
  }
  const toml::node* distance_node = table.get("distance_m");
  if (distance_node == nullptr)
    return make_error(Errc::invalid_frame,
                      toml_place(source, table) + ": " + section + " needs 'distance_m' or 'path'");
  auto distance = toml_number(source, table, "distance_m", 0.0, 0.0, max_distance_m);
  if (!distance) return distance.error();
  auto speed = toml_number(source, table, "speed_mps", 0.0, -1000.0, 1000.0);
  if (!speed) return speed.error();
  target.motion = *speed == 0.0 ? Motion::fixed(*distance) : Motion::constant_speed(*distance, *speed);
  return target;
}

Result<Scene> from_table(const toml::table& root, std::string_view source) {
  if (auto keys = check_keys(source, root, {"targets", "dust", "ambient_noise"}, "the scene"); !keys)
    return keys.error();
  Scene scene;
  auto dust = toml_number(source, root, "dust", 0.0, 0.0, 1.0);
  if (!dust) return dust.error();
  scene.dust = *dust;
  auto noise = toml_number(source, root, "ambient_noise", 0.5, 0.0, 100.0);
  if (!noise) return noise.error();
  scene.ambient_noise = *noise;
  if (const toml::node* node = root.get("targets")) {
    const toml::array* targets = node->as_array();
    if (targets == nullptr)
      return make_error(Errc::invalid_frame, where(source, *node, "targets") + " must be [[targets]] tables");
    for (std::size_t i = 0; i < targets->size(); ++i) {
      const toml::table* table = (*targets)[i].as_table();
      if (table == nullptr)
        return make_error(Errc::invalid_frame, where(source, (*targets)[i], "targets") + " entries must be tables");
      auto target = toml_target(source, *table, i);
      if (!target) return target.error();
      scene.targets.push_back(std::move(*target));
    }
  }
  return scene;
}

}  // namespace

Scene default_scene() {
  Scene scene;
  scene.targets.push_back(SceneTarget{"wall", Motion::fixed(50.0), 0.9, false});
  return scene;
}

Result<Scene> parse_scene(std::string_view toml_text, std::string_view source) {
  const std::string name(source);
  auto root = parse_toml(toml_text, name);
  if (!root) return std::move(root).error();
  return from_table(*root, name);
}

Result<Scene> load_scene(const std::string& path) {
  std::ifstream file(path);
  if (!file) return make_error(Errc::io, path + ": cannot open the scene file");
  std::stringstream text;
  text << file.rdbuf();
  return parse_scene(text.str(), path);
}

Result<Scene> scene_from_json(const nlohmann::json& object) {
  // The control socket's scene: the same keys as the TOML file, as JSON.
  if (!object.is_object()) return make_error(Errc::invalid_frame, "the scene must be an object");
  toml::table root;
  try {
    for (const auto& [key, value] : object.items()) {
      if (key == "targets") {
        if (!value.is_array()) return make_error(Errc::invalid_frame, "'targets' must be an array");
        toml::array targets;
        for (const auto& entry : value) {
          if (!entry.is_object()) return make_error(Errc::invalid_frame, "'targets' entries must be objects");
          toml::table target;
          for (const auto& [k, v] : entry.items()) {
            if (v.is_boolean()) {
              target.insert(k, v.get<bool>());
            } else if (v.is_number()) {
              target.insert(k, v.get<double>());
            } else if (v.is_string()) {
              target.insert(k, v.get<std::string>());
            } else if (v.is_array()) {
              toml::array points;
              for (const auto& p : v) {
                toml::array pair;
                if (p.is_array()) {
                  for (const auto& x : p) {
                    if (x.is_number()) pair.push_back(x.get<double>());
                  }
                }
                points.push_back(std::move(pair));
              }
              target.insert(k, std::move(points));
            } else {
              return make_error(Errc::invalid_frame, "target key '" + k + "' has an unsupported value");
            }
          }
          targets.push_back(std::move(target));
        }
        root.insert("targets", std::move(targets));
      } else if (value.is_number()) {
        root.insert(key, value.get<double>());
      } else {
        return make_error(Errc::invalid_frame, "scene key '" + key + "' must be a number");
      }
    }
  } catch (const nlohmann::json::exception& error) {
    return make_error(Errc::invalid_frame, error.what());
  }
  return from_table(root, "control");
}

}  // namespace rangekit::uls::emulator
