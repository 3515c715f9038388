// What `info` and `get` print, for both families: NAME=VALUE lines (the ULS adds a
// "# wire" comment), or with --json one JSON object of the same names and values,
// in the same order (issue 11 point 5).
#pragma once

#include <fmt/core.h>

#include <nlohmann/json.hpp>
#include <string>

namespace rangekit::cli {

class KeyValues {
 public:
  explicit KeyValues(bool json) : json_(json) {}
  void add(const std::string& key, const std::string& value, const std::string& comment = "") {
    if (json_) {
      object_[key] = value;
    } else if (comment.empty()) {
      fmt::print("{}={}\n", key, value);
    } else {
      fmt::print("{}={}  # {}\n", key, value, comment);
    }
  }
  // Prints the JSON object; call once, after the last add() of a command that succeeded.
  void finish() const {
    if (json_) fmt::print("{}\n", object_.dump());
  }

 private:
  bool json_;
  nlohmann::ordered_json object_ = nlohmann::ordered_json::object();
};

}  // namespace rangekit::cli
