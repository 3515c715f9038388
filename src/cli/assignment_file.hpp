// `set --from FILE`: the lines `get` prints, read back as set's NAME=VALUE assignments, so a
// unit's settings go from one `get` into another unit's `set` with their spaces intact.
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "rangekit/core/result.hpp"

namespace rangekit::cli {

// NAME=VALUE per line; a `#` after whitespace starts a comment (get's wire comments), blank
// lines are skipped. "-" reads standard input. Errc::io when the file cannot be read,
// Errc::wrong_form naming FILE:LINE for a line that is not NAME=VALUE.
Result<std::vector<std::string>> read_assignments(const std::string& path);

// Adds `--from FILE` to a set subcommand, described alike for every family.
void add_from_option(CLI::App& set, std::string& path);

}  // namespace rangekit::cli
