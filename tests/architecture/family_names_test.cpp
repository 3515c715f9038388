// Generic code names no sensor family: outside a family's own folders and the registration
// list, no code token in the tree is a family's name (docs/architecture.md, "Families").
#include <gtest/gtest.h>
#include "build_paths.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace {

namespace fs = std::filesystem;

// The one file that names every family, one line each: every other list is generated from it.
const std::string registration_list = "families.cmake";

// The generic parts of the tree: each generic library's src/<library> and include/rangekit/<library>
// (the CLI has no public headers), the registrations' src/families, the Python and web folders and
// the CMake files. In a folder, a family's own part beside the shared one (a folder or a Python
// module named after it, web/src/uls/, python/rangekit/uls.py) is not generic.
const std::vector<std::string> generic_libraries = {"core",   "record", "hub", "web", "mqtt",
                                                    "modbus", "sinks",  "sim", "cli", "families"};
const std::vector<std::string> generic_folders = {"python/src", "python/rangekit", "web/src"};
const std::vector<std::string> generic_files = {"CMakeLists.txt", "python/CMakeLists.txt",
                                                registration_list};  // and cmake/*.cmake

const fs::path tree = rangekit::test::source_dir();

std::string text_of(const fs::path& file) {
  std::ifstream in(file);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

enum class Syntax { cpp, typescript, css, python, cmake };

// Other files (py.typed, .clang-tidy) hold no code.
std::optional<Syntax> syntax_of(const fs::path& file) {
  const auto extension = file.extension();
  if (extension == ".cpp" || extension == ".hpp" || extension == ".h") return Syntax::cpp;
  if (extension == ".ts" || extension == ".js" || extension == ".mjs") return Syntax::typescript;
  if (extension == ".css") return Syntax::css;
  if (extension == ".py" || extension == ".pyi") return Syntax::python;
  if (extension == ".cmake" || file.filename() == "CMakeLists.txt") return Syntax::cmake;
  return std::nullopt;
}

// Where the string literal opening at `open` ends (one past its closing quote).
std::size_t string_end(const std::string& text, std::size_t open) {
  for (std::size_t at = open + 1; at < text.size(); ++at) {
    if (text[at] == '\\') {
      ++at;
    } else if (text[at] == text[open]) {
      return at + 1;
    }
  }
  return text.size();
}

// Where the C++ raw string R"delimiter(...)delimiter" opening at `open` ends.
std::size_t raw_string_end(const std::string& text, std::size_t open) {
  const std::size_t paren = text.find('(', open);
  if (paren == std::string::npos) return text.size();
  const std::string close = ")" + text.substr(open + 2, paren - open - 2) + "\"";
  const std::size_t end = text.find(close, paren);
  return end == std::string::npos ? text.size() : end + close.size();
}

bool is_alnum(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; }
bool is_identifier(char c) { return is_alnum(c) || c == '_'; }

// The text with its comments blanked out, lines kept. String literals stay ("uls" in one is
// code); Python's docstrings go, since they are documentation like comments.
std::string without_comments(std::string text, Syntax syntax) {
  const bool slashes = syntax == Syntax::cpp || syntax == Syntax::typescript;
  const bool blocks = slashes || syntax == Syntax::css;
  const bool hashes = syntax == Syntax::python || syntax == Syntax::cmake;
  const std::string quotes = syntax == Syntax::cmake ? "\"" : syntax == Syntax::typescript ? "\"'`" : "\"'";
  const auto blank = [&](std::size_t from, std::size_t to) {
    for (std::size_t at = from; at < to && at < text.size(); ++at) {
      if (text[at] != '\n') text[at] = ' ';
    }
  };
  std::size_t at = 0;
  while (at < text.size()) {
    const std::string_view rest = std::string_view(text).substr(at);
    const char previous = at > 0 ? text[at - 1] : '\n';
    std::size_t end = at + 1;
    if ((slashes && rest.starts_with("//")) || (hashes && rest[0] == '#')) {
      end = std::min(text.find('\n', at), text.size());
      blank(at, end);
    } else if (blocks && rest.starts_with("/*")) {
      end = text.find("*/", at + 2);
      end = end == std::string::npos ? text.size() : end + 2;
      blank(at, end);
    } else if (syntax == Syntax::python && (rest.starts_with(R"(""")") || rest.starts_with("'''"))) {
      end = text.find(rest.substr(0, 3), at + 3);
      end = end == std::string::npos ? text.size() : end + 3;
      blank(at, end);
    } else if (syntax == Syntax::cpp && rest.starts_with("R\"") && !is_identifier(previous)) {
      end = raw_string_end(text, at);
    } else if (quotes.find(rest[0]) != std::string::npos &&
               !(rest[0] == '\'' && syntax == Syntax::cpp && is_alnum(previous))) {
      end = string_end(text, at);  // in C++ a ' after a digit separates digits (16'384)
    }
    at = end;
  }
  return text;
}

// The families, from the registration list's set(RANGEKIT_FAMILIES name...), comments left out.
std::vector<std::string> registered_family_names() {
  const std::string list = without_comments(text_of(tree / registration_list), Syntax::cmake);
  std::smatch set;
  if (!std::regex_search(list, set, std::regex(R"(set\(\s*RANGEKIT_FAMILIES\s+([^)]*)\))"))) return {};
  std::istringstream words(set[1]);
  std::vector<std::string> names;
  for (std::string name; words >> name;) names.push_back(name);
  return names;
}

struct Hit {
  int line;
  std::string token;
};

// Each place `code` names a family as a code token: as an identifier or a part of one, between
// non-alphanumerics (`_` included: add_uls_command, "uls", rangekit/uls/) or at a camelCase
// step (UlsPage, Ls5Page, readULS), in any case.
std::vector<Hit> family_tokens(const std::string& code, const std::vector<std::string>& names) {
  std::string lower = code;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const auto upper_at = [&](std::size_t at) { return std::isupper(static_cast<unsigned char>(code[at])) != 0; };
  const auto lower_or_digit_at = [&](std::size_t at) { return is_alnum(code[at]) && !upper_at(at); };
  std::map<std::size_t, Hit> hits;  // by position, so they come in the file's order
  for (const std::string& name : names) {
    for (std::size_t start = lower.find(name); start != std::string::npos; start = lower.find(name, start + 1)) {
      const std::size_t end = start + name.size();
      const bool starts = start == 0 || !is_alnum(code[start - 1]) || (upper_at(start) && lower_or_digit_at(start - 1));
      const bool ends =
          end == code.size() || !is_alnum(code[end]) ||
          (upper_at(end) && (lower_or_digit_at(end - 1) || (end + 1 < code.size() && lower_or_digit_at(end + 1))));
      if (!starts || !ends) continue;
      std::size_t first = start;
      std::size_t last = end;
      while (first > 0 && is_identifier(code[first - 1])) --first;
      while (last < code.size() && is_identifier(code[last])) ++last;
      const auto line = 1 + std::count(code.begin(), code.begin() + static_cast<std::ptrdiff_t>(start), '\n');
      hits[start] = {static_cast<int>(line), code.substr(first, last - first)};
    }
  }
  std::vector<Hit> ordered;
  ordered.reserve(hits.size());
  for (auto& [position, hit] : hits) ordered.push_back(std::move(hit));
  return ordered;
}

// Every generic file, relative to the tree.
std::vector<std::string> generic_paths(const std::vector<std::string>& names) {
  std::vector<std::string> paths = generic_files;
  for (const auto& entry : fs::directory_iterator(tree / "cmake")) {
    if (entry.path().extension() == ".cmake") paths.push_back(fs::relative(entry.path(), tree).string());
  }
  const auto family_part = [&](const fs::path& path) {
    const std::string name = path.extension() == ".py" ? path.stem().string() : path.filename().string();
    return std::find(names.begin(), names.end(), name) != names.end();
  };
  std::vector<std::string> folders = generic_folders;
  for (const std::string& library : generic_libraries) {
    folders.push_back("src/" + library);
    if (fs::exists(tree / "include/rangekit" / library)) folders.push_back("include/rangekit/" + library);
  }
  for (const std::string& folder : folders) {
    for (auto it = fs::recursive_directory_iterator(tree / folder); it != fs::recursive_directory_iterator(); ++it) {
      if (it.depth() == 0 && family_part(it->path())) {
        it.disable_recursion_pending();
        continue;
      }
      if (it->is_regular_file()) paths.push_back(fs::relative(it->path(), tree).string());
    }
  }
  std::erase_if(paths, [](const std::string& path) { return path == registration_list; });
  return paths;
}

// The generic files that name a family, with where.
std::map<std::string, std::vector<Hit>> generic_files_naming_a_family() {
  const std::vector<std::string> names = registered_family_names();
  std::map<std::string, std::vector<Hit>> found;
  for (const std::string& path : generic_paths(names)) {
    const auto syntax = syntax_of(path);
    if (!syntax) continue;
    auto hits = family_tokens(without_comments(text_of(tree / path), *syntax), names);
    if (!hits.empty()) found[path] = std::move(hits);
  }
  return found;
}

std::string where(const std::string& path, const std::vector<Hit>& hits) {
  constexpr std::size_t shown = 5;
  std::string text;
  for (std::size_t i = 0; i < hits.size() && i < shown; ++i) {
    text += "\n  " + path + ":" + std::to_string(hits[i].line) + ": `" + hits[i].token + "`";
  }
  if (hits.size() > shown) text += "\n  ... and " + std::to_string(hits.size() - shown) + " more";
  return text;
}

TEST(FamilyNames, GenericFilesNameNoFamily) {
  ASSERT_TRUE(fs::exists(tree / registration_list)) << registration_list << " is missing: it lists the families";
  ASSERT_FALSE(registered_family_names().empty()) << registration_list << " sets no RANGEKIT_FAMILIES";
  const auto found = generic_files_naming_a_family();
  for (const auto& [path, hits] : found) {
    ADD_FAILURE() << path << " is generic but names a family:" << where(path, hits)
                  << "\nGeneric code names no family: move the family's part into its folder, or ask the family "
                     "(core/family.hpp, hub/service_family.hpp, cli/cli_family.hpp).";
  }
}

TEST(FamilyNames, CountOfGenericFilesNamingAFamily) {
  const auto count = generic_files_naming_a_family().size();
  RecordProperty("generic_files_naming_a_family", static_cast<int>(count));
  std::cout << count << " generic files still name a family\n";
}

}  // namespace
