// docs/conformance.md names a test file for every LS5 decision: the file must
// exist and mention the row (e.g. a test named ...L14), so the table stays true.
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

TEST(Ls5ConformanceTable, EveryRowNamesAnExistingTestThatHoldsIt) {
  const std::string root = RANGEKIT_SOURCE_DIR;
  const std::string doc = read_file(root + "/docs/conformance.md");
  ASSERT_FALSE(doc.empty());
  const std::regex row_pattern(R"(^\| (L[0-9]+) \|.*$)");
  const std::regex test_pattern("`(tests/ls5/[A-Za-z0-9_]+\\.cpp)`");
  std::istringstream lines(doc);
  std::string line;
  int rows = 0;
  while (std::getline(lines, line)) {
    std::smatch row;
    if (!std::regex_match(line, row, row_pattern)) continue;
    const std::string id = row[1];
    ++rows;
    int files = 0;
    for (auto it = std::sregex_iterator(line.begin(), line.end(), test_pattern); it != std::sregex_iterator(); ++it) {
      const std::string path = (*it)[1];
      std::string file = root;
      file.append("/").append(path);
      const std::string text = read_file(file);
      EXPECT_FALSE(text.empty()) << id << ": " << path << " missing";
      // "L1" must not match "L10": the id is followed by a non-digit.
      EXPECT_TRUE(std::regex_search(text, std::regex(id + "(?![0-9])")))
          << id << ": " << path << " does not mention it";
      ++files;
    }
    EXPECT_GT(files, 0) << id << " names no test in tests/ls5";
  }
  EXPECT_GE(rows, 24);
}

}  // namespace
