// `--help` that fits an 80-column terminal: CLI11 prints each description on one line, so
// lines past the width are broken between words and continued under their own column.
#include "cli/help_width.hpp"

#include <sstream>

namespace rangekit::cli {
namespace {

// Where a too long line continues: under its description (the text after the first gap of
// two spaces, "  --port TEXT    the port ..."), under its own text when it is indented (a
// description on a line of its own), or two in (a footer).
std::size_t hanging_indent(const std::string& line) {
  const std::size_t text = line.find_first_not_of(' ');
  if (text == std::string::npos) return 0;
  const std::size_t gap = line.find("  ", text);
  if (gap != std::string::npos) {
    const std::size_t description = line.find_first_not_of(' ', gap);
    if (description <= help_width / 2) return description;  // npos is past it too
  }
  return text == 0 ? 2 : text;
}

void append_wrapped(std::string& out, const std::string& line) {
  if (line.size() <= help_width) {
    out += line;
    return;
  }
  const std::size_t indent = hanging_indent(line);
  std::size_t start = 0;
  std::string prefix;
  while (line.size() - start + prefix.size() > help_width) {
    // The last space that keeps the line within the width, past the indentation; a word
    // longer than the room (a path) stays whole on a line of its own.
    const std::size_t room = help_width - prefix.size();
    std::size_t cut = line.rfind(' ', start + room);
    if (cut == std::string::npos || cut <= start + (prefix.empty() ? indent : 0)) {
      cut = line.find(' ', start + room);
      if (cut == std::string::npos) break;
    }
    out += prefix + line.substr(start, cut - start) + "\n";
    start = line.find_first_not_of(' ', cut);
    if (start == std::string::npos) return;
    prefix.assign(indent, ' ');
  }
  out += prefix + line.substr(start);
}

}  // namespace

std::string wrap_help(const std::string& text) {
  std::string out;
  std::istringstream lines(text);
  std::string line;
  bool first = true;
  while (std::getline(lines, line)) {
    if (!first) out += '\n';
    first = false;
    append_wrapped(out, line);
  }
  if (!text.empty() && text.back() == '\n') out += '\n';
  return out;
}

std::string WrappingFormatter::make_help(const CLI::App* app, std::string name, CLI::AppFormatMode mode) const {
  return wrap_help(CLI::Formatter::make_help(app, std::move(name), mode));
}

}  // namespace rangekit::cli
