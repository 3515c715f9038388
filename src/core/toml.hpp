// Reading a TOML text, for the files rangekit reads (ULS and LS5 host configuration,
// emulator scenes). Needs toml++, which the libraries that read TOML link; nothing else
// in core does.
#pragma once

#include <toml++/toml.h>

#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "rangekit/core/result.hpp"
#include "rangekit/core/text.hpp"

namespace rangekit {

// The root table of `text`, or invalid_frame "<source_name>:<line>: <what is wrong>".
inline Result<toml::table> parse_toml(std::string_view text, std::string_view source_name) {
  const auto failure = [&](const toml::parse_error& error) {
    return make_error(Errc::invalid_frame, std::string(source_name) + ":" + std::to_string(error.source().begin.line) +
                                               ": " + text::printable(error.description()));
  };
#if TOML_EXCEPTIONS
  try {
    return toml::parse(text, source_name);
  } catch (const toml::parse_error& error) {
    return failure(error);
  }
#else
  toml::parse_result parsed = toml::parse(text, source_name);
  if (!parsed) return failure(parsed.error());
  return std::move(parsed).table();
#endif
}

// "<source_name>:<line>" of a node, the start of every message about a TOML value.
inline std::string toml_place(std::string_view source_name, const toml::node& node) {
  return std::string(source_name) + ":" + std::to_string(node.source().begin.line);
}

// The first key of `table` not among `known`, with its node; nullopt when every key is known.
struct TomlKey {
  std::string_view key;
  const toml::node* node;
};
inline std::optional<TomlKey> first_unknown_key(const toml::table& table,
                                                std::initializer_list<std::string_view> known) {
  for (const auto& [key, node] : table) {
    bool found = false;
    for (const std::string_view name : known) found = found || key.str() == name;
    if (!found) return TomlKey{key.str(), &node};
  }
  return std::nullopt;
}

}  // namespace rangekit
