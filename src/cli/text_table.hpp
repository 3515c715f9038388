// A table for `rangekit tables`: rows collected first so plain columns can be aligned,
// or printed as Markdown.
#pragma once

#include <fmt/core.h>

#include <algorithm>
#include <string>
#include <vector>

namespace rangekit::cli {

class TextTable {
 public:
  explicit TextTable(std::vector<std::string> header) : rows_{std::move(header)} {}
  void add(std::vector<std::string> cells) { rows_.push_back(std::move(cells)); }

  void print(bool markdown) const {
    std::vector<std::size_t> widths(rows_.front().size(), 0);
    for (const auto& cells : rows_) {
      for (std::size_t i = 0; i < cells.size(); ++i) widths[i] = std::max(widths[i], cells[i].size());
    }
    for (std::size_t r = 0; r < rows_.size(); ++r) {
      std::string line;
      for (std::size_t i = 0; i < rows_[r].size(); ++i) {
        if (markdown) {
          line += "| " + rows_[r][i] + " ";
        } else {
          const bool last = i + 1 == rows_[r].size();
          line += last ? rows_[r][i] : fmt::format("{:<{}}  ", rows_[r][i], widths[i]);
        }
      }
      fmt::print("{}{}\n", line, markdown ? "|" : "");
      if (markdown && r == 0) {
        std::string rule;
        for (std::size_t i = 0; i < rows_[0].size(); ++i) rule += "|---";
        fmt::print("{}|\n", rule);
      }
    }
  }

 private:
  std::vector<std::vector<std::string>> rows_;
};

}  // namespace rangekit::cli
