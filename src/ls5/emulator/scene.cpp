// Scene files for the LS5 emulator (TOML, docs/emulator-ls5.md "Scene").

#include <fstream>
#include <sstream>

#include "rangekit/ls5/emulator/firmware.hpp"
#include "sim/scene_toml.hpp"

namespace rangekit::ls5::emulator {

namespace {

// Keys are named plainly in messages: "scene.toml:3: reflectivity must be within 0 .. 1"
// (docs/emulator-ls5.md).
std::string where(const std::string& source, const toml::node& node, std::string_view key) {
  return sim::where(source, node, key, sim::KeyStyle::plain);
}

Result<double> number(const std::string& source, const toml::table& table, std::string_view key, double fallback,
                      double min, double max) {
  return sim::number(source, table, key, fallback, min, max, sim::KeyStyle::plain);
}

Status check_keys(const std::string& source, const toml::table& table, std::initializer_list<std::string_view> known,
                  std::string_view section) {
  return sim::check_keys(source, table, known, section, sim::KeyStyle::plain);
}

Result<Scene> from_table(const toml::table& root, const std::string& source) {
  Scene scene;
  if (auto known = check_keys(source, root, {"target", "dust", "dropout"}, "the scene"); !known) {
    return std::move(known).error();
  }
  if (const toml::node* target_node = root.get("target")) {
    const toml::table* target = target_node->as_table();
    if (!target) return make_error(Errc::invalid_frame, where(source, *target_node, "target") + " must be a table");
    if (auto known =
            check_keys(source, *target, {"position_mm", "speed_mm_per_s", "path", "repeat", "reflectivity", "noise_mm"},
                       "[target]");
        !known) {
      return std::move(known).error();
    }
    auto reflectivity = number(source, *target, "reflectivity", 1.0, 0.0, 1.0);
    if (!reflectivity) return std::move(reflectivity).error();
    scene.reflectivity = *reflectivity;
    auto noise = number(source, *target, "noise_mm", -1.0, 0.0, 1e6);
    if (!noise && target->get("noise_mm")) return std::move(noise).error();
    if (noise) scene.noise_mm = *noise;
    if (const toml::node* path_node = target->get("path")) {
      const toml::array* path = path_node->as_array();
      if (!path) return make_error(Errc::invalid_frame, where(source, *path_node, "target.path") + " must be an array");
      std::vector<PathPoint> points;
      for (const auto& item : *path) {
        const toml::array* pair = item.as_array();
        if (!pair || pair->size() != 2 || !(*pair)[0].value<double>() || !(*pair)[1].value<double>()) {
          return make_error(Errc::invalid_frame,
                            where(source, item, "target.path") + " entries must be [time_s, position_mm]");
        }
        points.push_back(PathPoint{*(*pair)[0].value<double>(), *(*pair)[1].value<double>()});
      }
      const bool repeat = target->get("repeat") ? target->get("repeat")->value_or(false) : false;
      auto motion = Motion::path(std::move(points), repeat);
      if (!motion)
        return make_error(Errc::invalid_frame,
                          where(source, *path_node, "target.path") + ": " + motion.error().message);
      scene.target = std::move(*motion);
      scene.target_set = true;
    } else if (target->get("position_mm")) {
      auto position = number(source, *target, "position_mm", 0, -max_scene_position_mm, max_scene_position_mm);
      if (!position) return std::move(position).error();
      auto speed = number(source, *target, "speed_mm_per_s", 0, -max_scene_speed_mm_per_s, max_scene_speed_mm_per_s);
      if (!speed) return std::move(speed).error();
      scene.target = Motion::constant_speed(*position, *speed);
      scene.target_set = true;
    }
  }
  if (const toml::node* dust_node = root.get("dust")) {
    const toml::table* dust = dust_node->as_table();
    if (!dust) return make_error(Errc::invalid_frame, where(source, *dust_node, "dust") + " must be a table");
    if (auto known = check_keys(source, *dust, {"probability"}, "[dust]"); !known) return std::move(known).error();
    auto probability = number(source, *dust, "probability", 0, 0, 1);
    if (!probability) return std::move(probability).error();
    scene.dust_probability = *probability;
  }
  if (const toml::node* dropouts_node = root.get("dropout")) {
    const toml::array* dropouts = dropouts_node->as_array();
    if (!dropouts) {
      return make_error(Errc::invalid_frame, where(source, *dropouts_node, "dropout") + " must be [[dropout]] tables");
    }
    for (const auto& item : *dropouts) {
      const toml::table* dropout = item.as_table();
      if (!dropout) return make_error(Errc::invalid_frame, where(source, item, "dropout") + " must be a table");
      if (auto known = check_keys(source, *dropout, {"start_s", "end_s", "kind"}, "[[dropout]]"); !known) {
        return std::move(known).error();
      }
      auto start = number(source, *dropout, "start_s", -1, 0, 1e9);
      auto end = number(source, *dropout, "end_s", -1, 0, 1e9);
      if (!start) return std::move(start).error();
      if (!end) return std::move(end).error();
      if (*start < 0 || *end <= *start) {
        return make_error(Errc::out_of_range,
                          where(source, item, "dropout") + " needs start_s and end_s with end_s > start_s");
      }
      Dropout entry{*start, *end, "shading"};
      if (const toml::node* kind = dropout->get("kind")) {
        const auto text = kind->value<std::string>();
        if (!text || (*text != "shading" && *text != "dust")) {
          return make_error(Errc::invalid_frame,
                            where(source, *kind, "dropout.kind") + " must be \"shading\" or \"dust\"");
        }
        entry.kind = *text;
      }
      scene.dropouts.push_back(entry);
    }
  }
  return scene;
}

}  // namespace

Result<Scene> parse_scene(std::string_view text, const std::string& source_name) {
  auto root = parse_toml(text, source_name);
  if (!root) return std::move(root).error();
  return from_table(*root, source_name);
}

Result<Scene> load_scene(const std::string& path) {
  std::ifstream file(path);
  if (!file) return make_error(Errc::io, path + ": cannot open the scene file");
  std::stringstream text;
  text << file.rdbuf();
  return parse_scene(text.str(), path);
}

}  // namespace rangekit::ls5::emulator
