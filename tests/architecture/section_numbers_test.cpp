// Messages say what is wrong in words: a document's section numbers (§8, §10.1) belong in
// docs/conformance.md and a command's --help footer, not in what a user reads when it fails.
#include <gtest/gtest.h>
#include "build_paths.hpp"

#include <filesystem>
#include <fstream>
#include <regex>
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

TEST(Messages, NameNoSectionOfTheDocuments) {
  const fs::path tree = rangekit::test::source_dir();
  std::vector<std::string> offenders;
  for (const char* top : {"src", "include"}) {
    for (const auto& entry : fs::recursive_directory_iterator(tree / top)) {
      const std::string path = fs::relative(entry.path(), tree).string();
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

}  // namespace
