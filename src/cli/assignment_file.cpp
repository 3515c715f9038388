#include "cli/assignment_file.hpp"

#include <cerrno>
#include <fstream>
#include <iostream>
#include <system_error>

#include "rangekit/core/text.hpp"

namespace rangekit::cli {
namespace {

std::string_view trimmed(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r')) text.remove_suffix(1);
  return text;
}

// "mode=binning  # MM=2" -> "mode=binning"; a '#' inside a value (no space before it) stays.
std::string_view without_comment(std::string_view line) {
  for (std::size_t at = line.find('#'); at != std::string_view::npos; at = line.find('#', at + 1)) {
    if (at == 0 || line[at - 1] == ' ' || line[at - 1] == '\t') return line.substr(0, at);
  }
  return line;
}

}  // namespace

Result<std::vector<std::string>> read_assignments(const std::string& path) {
  std::ifstream file;
  if (path != "-") {
    file.open(path);
    if (!file) return make_error(Errc::io, "cannot read " + path + ": " + std::generic_category().message(errno));
  }
  std::istream& in = path == "-" ? std::cin : file;
  const std::string name = path == "-" ? "standard input" : path;
  std::vector<std::string> assignments;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const std::string_view assignment = trimmed(without_comment(line));
    if (assignment.empty()) continue;
    if (assignment.find('=') == std::string_view::npos || assignment.front() == '=') {
      return make_error(Errc::wrong_form, name + ":" + std::to_string(number) + ": '" + text::printable(assignment) +
                                              "' is not NAME=VALUE");
    }
    assignments.emplace_back(assignment);
  }
  if (in.bad()) return make_error(Errc::io, "cannot read " + name);
  return assignments;
}

void add_from_option(CLI::App& set, std::string& path) {
  set.add_option("--from", path,
                 "NAME=VALUE lines from FILE ('-': standard input), e.g. what `get` printed; read-only "
                 "names in it are skipped");
}

}  // namespace rangekit::cli
