// Messages say what is wrong in words: a document's section numbers (§8, §10.1) belong in
// docs/conformance.md and a command's --help footer, not in what a user reads when it fails.
// The dashboard likewise: its pages name the sections once, in the foot of each family's page.
#include <gtest/gtest.h>
#include "build_paths.hpp"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// Where a section number is the point: the tables `rangekit tables` prints (their reference
// column), the protocol walkthroughs of `rangekit demo`, which cite the line they show.
const std::regex section_citing_file(
    R"((src/uls/commands\.cpp|src/ls5/parameters\.cpp|src/[a-z0-9]+/cli/[a-z0-9]+_demo\.cpp)$)");

// The string literals of one line of C++, with the comment after them dropped; `in_block`
// carries a /* comment over lines.
std::vector<std::string> string_literals_of(const std::string& line, bool& in_block) {
  std::vector<std::string> found;
  for (std::size_t at = 0; at < line.size();) {
    if (in_block) {
      const std::size_t end = line.find("*/", at);
      if (end == std::string::npos) return found;
      in_block = false;
      at = end + 2;
    } else if (line.compare(at, 2, "//") == 0) {
      return found;
    } else if (line.compare(at, 2, "/*") == 0) {
      in_block = true;
      at += 2;
    } else if (line[at] == '\'') {  // a character literal: '"' is no string
      at = std::min(line.find('\'', at + (line[at + 1] == '\\' ? 3 : 2)), line.size()) + 1;
    } else if (line[at] == '"') {
      std::string literal;
      for (++at; at < line.size() && line[at] != '"'; ++at) {
        if (line[at] == '\\' && at + 1 < line.size()) literal += line[at++];
        literal += line[at];
      }
      found.push_back(literal);
      ++at;
    } else {
      ++at;
    }
  }
  return found;
}

// A string literal of a TypeScript file and the line it starts on; `lead` is the statement's
// code before it ("export const DOCUMENT_SECTIONS =").
struct ScriptLiteral {
  std::size_t line;
  std::string text;
  std::string lead;
};

// Whether a `/` after `code` (the file up to it) starts a regular expression, not a division:
// after an operator, an opening bracket or a keyword, not after a value.
bool starts_a_regex(const std::string& code) {
  std::size_t end = code.find_last_not_of(" \t\r\n");
  if (end == std::string::npos) return true;
  if (std::string("(,=:[!&|?{};+-*%<>~^").find(code[end]) != std::string::npos) return true;
  std::size_t start = end + 1;
  while (start > 0 && (std::isalnum(static_cast<unsigned char>(code[start - 1])) || code[start - 1] == '_')) --start;
  const std::string word = code.substr(start, end + 1 - start);
  return word == "return" || word == "typeof" || word == "case" || word == "in" || word == "of" || word == "void";
}

// The string literals of a TypeScript file: '...', "..." and `...`, a template's ${...} read as
// code (a literal inside it is one of its own); comments and regular expressions are skipped.
std::vector<ScriptLiteral> script_literals_of(const std::string& source) {
  std::vector<ScriptLiteral> found;
  std::vector<ScriptLiteral> templates;  // open template literals, the innermost last
  std::vector<bool> braces;              // open braces of the code, true for a template's ${
  std::string code;                      // the code read so far, without literals and comments
  std::string statement;                 // the current statement's code
  std::size_t line = 1;
  bool in_template = false;
  const auto count_lines = [&](std::size_t from, std::size_t to) {
    for (std::size_t at = from; at < to && at < source.size(); ++at) line += source[at] == '\n' ? 1 : 0;
  };
  for (std::size_t at = 0; at < source.size(); ++at) {
    const char c = source[at];
    if (in_template) {
      if (c == '`') {
        found.push_back(templates.back());
        templates.pop_back();
        in_template = false;
        code += '`';
      } else if (c == '$' && source.compare(at, 2, "${") == 0) {
        braces.push_back(true);
        in_template = false;
        code += '{';
        ++at;
      } else {
        const std::size_t width = c == '\\' && at + 1 < source.size() ? 2 : 1;
        templates.back().text += source.substr(at, width);
        count_lines(at, at + width);
        at += width - 1;
      }
      continue;
    }
    if (source.compare(at, 2, "//") == 0) {
      at = std::min(source.find('\n', at), source.size()) - 1;
    } else if (source.compare(at, 2, "/*") == 0) {
      const std::size_t end = std::min(source.find("*/", at + 2), source.size());
      count_lines(at, end);
      at = end + 1;
    } else if (c == '/' && starts_a_regex(code)) {
      bool in_class = false;
      for (++at; at < source.size() && source[at] != '\n' && (in_class || source[at] != '/'); ++at) {
        if (source[at] == '\\')
          ++at;
        else if (source[at] == '[')
          in_class = true;
        else if (source[at] == ']')
          in_class = false;
      }
      if (at < source.size() && source[at] == '\n') --at;  // not a regex after all: the line still counts
      code += "/re/";
    } else if (c == '\'' || c == '"') {
      ScriptLiteral literal{line, "", statement};
      for (++at; at < source.size() && source[at] != c && source[at] != '\n'; ++at) {
        if (source[at] == '\\' && at + 1 < source.size()) literal.text += source[at++];
        literal.text += source[at];
      }
      if (at < source.size() && source[at] == '\n') --at;  // unterminated: the line still counts
      found.push_back(literal);
      code += c;
    } else if (c == '`') {
      templates.push_back({line, "", statement});
      in_template = true;
    } else {
      if (c == '\n') ++line;
      if (c == '}' && !braces.empty()) {
        const bool closes_a_template = braces.back();
        braces.pop_back();
        if (closes_a_template) {
          in_template = true;
          continue;
        }
      }
      if (c == '{') braces.push_back(false);
      code += c;
      statement = c == ';' || c == '{' || c == '}' ? "" : statement + c;
    }
  }
  return found;
}

// A family page's foot, the one place the dashboard names the sections: web/src/FAMILY/index.ts's
// DOCUMENT_SECTIONS (shown by main.ts below the page).
const std::regex dashboard_foot_file(R"(web/src/[a-z0-9_]+/index\.ts$)");

TEST(Messages, NameNoSectionOfTheDocuments) {
  const fs::path source_tree = rangekit::test::source_dir();
  std::vector<std::string> offenders;
  for (const char* top : {"src", "include"}) {
    for (const auto& entry : fs::recursive_directory_iterator(source_tree / top)) {
      const std::string path = fs::relative(entry.path(), source_tree).string();
      if (!entry.is_regular_file() || std::regex_search(path, section_citing_file)) continue;
      if (entry.path().extension() != ".cpp" && entry.path().extension() != ".hpp") continue;
      std::ifstream in(entry.path());
      bool in_block = false;
      std::size_t number = 0;
      for (std::string line; std::getline(in, line);) {
        ++number;
        if (line.find("footer(") != std::string::npos) continue;  // --help's last lines
        for (const std::string& literal : string_literals_of(line, in_block)) {
          if (literal.find("§") != std::string::npos)
            offenders.push_back(path + ":" + std::to_string(number) + ": " + literal);
        }
      }
    }
  }
  std::string list;
  for (const auto& offender : offenders) list += "\n  " + offender;
  EXPECT_TRUE(offenders.empty()) << "say it in words, and keep the section in docs/conformance.md:" << list;
}

// The dashboard's texts too, and also "table 9.2" or "formula 8.3": a label, hint or message
// says it in words; the foot of a family's page names the document's sections once.
TEST(Messages, DashboardNamesNoSectionOutsideAPagesFoot) {
  const fs::path source_tree = rangekit::test::source_dir();
  const std::regex cites(R"(§|\b(table|formulas?) [0-9]+\.[0-9])", std::regex::icase);
  std::vector<std::string> offenders;
  std::size_t feet = 0;
  for (const auto& entry : fs::recursive_directory_iterator(source_tree / "web/src")) {
    if (!entry.is_regular_file() || entry.path().extension() != ".ts") continue;
    const std::string path = fs::relative(entry.path(), source_tree).string();
    std::ifstream in(entry.path());
    std::stringstream source;
    source << in.rdbuf();
    for (const ScriptLiteral& literal : script_literals_of(source.str())) {
      if (!std::regex_search(literal.text, cites)) continue;
      const bool foot = std::regex_search(path, dashboard_foot_file) &&
                        std::regex_search(literal.lead, std::regex(R"(^\s*(export\s+)?const\s+DOCUMENT_SECTIONS\s*=)"));
      if (foot)
        ++feet;
      else
        offenders.push_back(path + ":" + std::to_string(literal.line) + ": " + literal.text);
    }
  }
  EXPECT_GT(feet, 0U) << "no family page names its document's sections in DOCUMENT_SECTIONS";
  std::string list;
  for (const auto& offender : offenders) list += "\n  " + offender;
  EXPECT_TRUE(offenders.empty()) << "say it in words; the page's foot (DOCUMENT_SECTIONS) names the sections:" << list;
}

}  // namespace
