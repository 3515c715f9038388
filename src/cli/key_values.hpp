// What `info` and `get` print, for both families (U96, docs/cli.md): NAME=VALUE lines,
// kebab names ending in the unit (`period-ms=10`) and bare values, or with --json one
// object of the same names in the same order, numbers as numbers.
#pragma once

#include <fmt/core.h>

#include <nlohmann/json.hpp>
#include <string>

#include "rangekit/core/text.hpp"

namespace rangekit::cli {

class KeyValues {
 public:
  explicit KeyValues(bool json) : json_(json) {}
  // A text value: a JSON string.
  void add(const std::string& key, const std::string& value, const std::string& comment = "") {
    if (json_) {
      object_[key] = value;
    } else {
      print(key, value, comment);
    }
  }
  // A number ("10", "0.2") or a list of numbers ("2000,2000,2000"): JSON numbers;
  // text that is not one stays a string.
  void add_number(const std::string& key, const std::string& value, const std::string& comment = "") {
    if (!json_) {
      print(key, value, comment);
      return;
    }
    nlohmann::ordered_json numbers = nlohmann::ordered_json::array();
    std::string_view rest = value;
    while (true) {
      const auto comma = rest.find(',');
      const std::string_view part = rest.substr(0, comma);
      if (auto whole = text::parse_unsigned(part)) {
        numbers.push_back(*whole);
      } else if (auto decimal = text::parse_decimal(part)) {
        numbers.push_back(*decimal);
      } else {
        object_[key] = value;
        return;
      }
      if (comma == std::string_view::npos) break;
      rest = rest.substr(comma + 1);
    }
    if (numbers.size() == 1) {
      object_[key] = numbers[0];
    } else {
      object_[key] = numbers;
    }
  }
  // Prints the JSON object; call once, after the last add() of a command that succeeded.
  void finish() const {
    if (json_) fmt::print("{}\n", object_.dump());
  }

 private:
  static void print(const std::string& key, const std::string& value, const std::string& comment) {
    if (comment.empty()) {
      fmt::print("{}={}\n", key, value);
    } else {
      fmt::print("{}={}  # {}\n", key, value, comment);
    }
  }

  bool json_;
  nlohmann::ordered_json object_ = nlohmann::ordered_json::object();
};

}  // namespace rangekit::cli
