// `--help` within an 80-column terminal, for every subcommand (main.cpp sets it on the app
// before the subcommands are added, and they take it over).
#pragma once

#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>

namespace rangekit::cli {

inline constexpr std::size_t help_width = 80;

// Lines longer than help_width broken between words, continued under their description.
std::string wrap_help(const std::string& text);

class WrappingFormatter : public CLI::Formatter {
 public:
  std::string make_help(const CLI::App* app, std::string name, CLI::AppFormatMode mode) const override;
};

}  // namespace rangekit::cli
