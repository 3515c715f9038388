// docs/conformance.md names a test file for every decision; for the ULS rows
// (and shared rows pointing into tests/uls) the file must exist and mention the row.
#include <gtest/gtest.h>

#include <fstream>
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

bool mentions(const std::string& text, const std::string& row) {
  // "U4" must not match "U40": the id is followed by a non-digit.
  const std::regex id(row + "(?![0-9])");
  return std::regex_search(text, id);
}

TEST(UlsConformanceTable, EveryRowNamesAnExistingTestThatHoldsIt) {
  const std::string root = RANGEKIT_SOURCE_DIR;
  const std::string doc = read_file(root + "/docs/conformance.md");
  ASSERT_FALSE(doc.empty());
  const std::regex row_pattern(R"(^\| ((?:U|F)[0-9]+) \|.*$)");
  const std::regex test_pattern("`(tests/uls/[A-Za-z0-9_]+\\.cpp)`");
  std::istringstream lines(doc);
  std::string line;
  int uls_rows = 0;
  while (std::getline(lines, line)) {
    std::smatch row;
    if (!std::regex_match(line, row, row_pattern)) continue;
    const std::string id = row[1];
    const bool uls_row = id[0] == 'U';
    uls_rows += uls_row ? 1 : 0;
    int files = 0;
    for (auto it = std::sregex_iterator(line.begin(), line.end(), test_pattern); it != std::sregex_iterator(); ++it) {
      const std::string path = (*it)[1];
      const std::string text = read_file(root + "/" + path);
      EXPECT_FALSE(text.empty()) << id << ": " << path << " missing";
      EXPECT_TRUE(mentions(text, id)) << id << ": " << path << " does not mention " << id;
      ++files;
    }
    if (uls_row) {
      EXPECT_GT(files, 0) << id << " names no test in tests/uls";
    }
  }
  EXPECT_GE(uls_rows, 34);
}

}  // namespace
