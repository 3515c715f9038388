// Reading the fields of an emulator scene file (TOML), shared by the ULS and LS5 scenes.
// Private to rangekit::sim.
#pragma once

#include <initializer_list>
#include <string>
#include <string_view>

#include "core/toml.hpp"  // private: toml++ is no part of the public API
#include "rangekit/core/result.hpp"
#include "rangekit/core/text.hpp"

namespace rangekit::sim {

// How a message names a key: "s.toml:3: 'reflectivity'" (ULS scenes, docs/emulator-uls.md)
// or "s.toml:3: reflectivity" (LS5 scenes, docs/emulator-ls5.md).
enum class KeyStyle { quoted, plain };

inline std::string where(std::string_view source, const toml::node& node, std::string_view key, KeyStyle style) {
  // A key may hold any character, NUL and escape sequences too: shown escaped.
  const std::string shown = text::printable(key);
  const std::string name = style == KeyStyle::quoted ? "'" + shown + "'" : shown;
  return toml_place(source, node) + ": " + name;
}

// The number at `key`, `fallback` when absent; bad_number or out_of_range naming file, line and key.
inline Result<double> number(std::string_view source, const toml::table& table, std::string_view key, double fallback,
                             double min, double max, KeyStyle style) {
  const toml::node* node = table.get(key);
  if (node == nullptr) return fallback;
  const auto value = node->value<double>();
  if (!value) return make_error(Errc::bad_number, where(source, *node, key, style) + " must be a number");
  if (*value < min || *value > max) {
    return make_error(Errc::out_of_range, where(source, *node, key, style) + " must be within " + std::to_string(min) +
                                              " .. " + std::to_string(max));
  }
  return *value;
}

// invalid_frame for the first key of `table` that is not in `known`.
inline Status check_keys(std::string_view source, const toml::table& table,
                         std::initializer_list<std::string_view> known, std::string_view section, KeyStyle style) {
  if (const auto unknown = first_unknown_key(table, known)) {
    return make_error(Errc::invalid_frame,
                      where(source, *unknown->node, unknown->key, style) + ": unknown key in " + std::string(section));
  }
  return ok_status();
}

}  // namespace rangekit::sim
