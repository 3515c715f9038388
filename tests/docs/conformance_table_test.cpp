// docs/conformance.md names a test file for every decision. For every row of
// every table (F, U, L, H, ...), each named file must exist and mention the
// row's id, so the page cannot drift from the tests that hold it.
#include <gtest/gtest.h>
#include "build_paths.hpp"

#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// "U4" must not match "U40": the id is followed by a non-digit.
bool mentions(const std::string& text, const std::string& id) {
  return std::regex_search(text, std::regex(id + "(?![0-9])"));
}

TEST(ConformanceTable, EveryRowNamesExistingTestsThatMentionIt) {
  const std::string root = rangekit::test::source_dir();
  const std::string doc = read_file(root + "/docs/conformance.md");
  ASSERT_FALSE(doc.empty()) << "docs/conformance.md not found under " << root;
  const std::regex row_pattern(R"(^\| ([A-Z][0-9]+) \|.*$)");
  // C++ tests, and the dashboard's browser tests (web/tests, node).
  const std::regex test_pattern("`((?:tests|web/tests)/[A-Za-z0-9_/.]+\\.(?:cpp|mjs))`");
  std::map<char, int> rows_per_table;
  std::istringstream lines(doc);
  std::string line;
  while (std::getline(lines, line)) {
    std::smatch row;
    if (!std::regex_match(line, row, row_pattern)) continue;
    const std::string id = row[1];
    ++rows_per_table[id[0]];
    int files = 0;
    for (auto it = std::sregex_iterator(line.begin(), line.end(), test_pattern); it != std::sregex_iterator(); ++it) {
      const std::string path = (*it)[1];
      const std::string text = read_file(root + "/" + path);
      EXPECT_FALSE(text.empty()) << id << ": " << path << " is missing";
      EXPECT_TRUE(mentions(text, id)) << id << ": " << path << " does not mention " << id;
      ++files;
    }
    EXPECT_GT(files, 0) << id << " names no test file";
  }
  EXPECT_GE(rows_per_table['F'], 5);
  EXPECT_GE(rows_per_table['U'], 34);
  EXPECT_GE(rows_per_table['L'], 25);
  EXPECT_GE(rows_per_table['H'], 2);
}

}  // namespace
