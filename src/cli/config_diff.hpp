// `config diff` (and the read-back check of `config load`/`reset`) for both families:
// one line `name: file=X device=Y` per setting that differs, names and values as `get`
// prints them, then one summary line; exit 1 when anything differs (docs/cli.md).
#pragma once

#include <fmt/core.h>

#include <string>
#include <string_view>
#include <vector>

#include "cli/commands.hpp"

namespace rangekit::cli {

struct DiffLine {
  std::string name;    // as `get` prints it: "long-gate-m", "period-ms"
  std::string wanted;  // the file's (or the factory's) value
  std::string device;  // the device's value
};

inline void print_diff_lines(const std::vector<DiffLine>& lines, std::string_view wanted_label = "file") {
  for (const DiffLine& line : lines)
    fmt::print("{}: {}={} device={}\n", line.name, wanted_label, line.wanted, line.device);
}

// The whole `config diff` output; returns its exit code (0 equal, 1 different, like diff(1)).
inline int print_config_diff(const std::vector<DiffLine>& lines, std::size_t compared) {
  print_diff_lines(lines);
  if (lines.empty()) {
    fmt::print("no differences ({} settings compared)\n", compared);
    return exit_ok;
  }
  fmt::print("{} of {} settings differ\n", lines.size(), compared);
  return 1;
}

}  // namespace rangekit::cli
