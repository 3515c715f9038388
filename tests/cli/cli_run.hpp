// Runs the built rangekit binary with a shell command line (stdin from `input`, or
// /dev/null without it; stderr merged into the output) for the end-to-end CLI tests.
#pragma once

#include <sys/wait.h>
#include <unistd.h>
#include "build_paths.hpp"

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace cli_test {

struct CliResult {
  int exit_code = -1;
  std::string output;
};

// Runs a shell command line to its end, stderr merged into the output.
inline CliResult run_shell(const std::string& command) {
  CliResult run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe != nullptr) {
    std::array<char, 4096> buffer{};
    std::size_t got = 0;
    while ((got = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.output.append(buffer.data(), got);
    const int status = ::pclose(pipe);
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  return run;
}

inline CliResult run_cli(const std::string& arguments, const std::string& input = "") {
  std::filesystem::path input_file = "/dev/null";
  if (!input.empty()) {
    input_file = std::filesystem::temp_directory_path() / ("rangekit-cli-" + std::to_string(::getpid()));
    std::ofstream(input_file, std::ios::binary) << input;
  }
  CliResult run =
      run_shell(std::string(rangekit::test::cli_path()) + " " + arguments + " < " + input_file.string() + " 2>&1");
  if (!input.empty()) std::filesystem::remove(input_file);
  return run;
}

inline std::size_t count_of(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace cli_test
