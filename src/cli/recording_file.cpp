#include "cli/recording_file.hpp"

#include <fmt/core.h>

#include <fstream>
#include <iterator>

#include "cli/commands.hpp"

namespace rangekit::cli {

std::string comment_value(const record::SerialRecording& recording, const std::string& key) {
  for (const std::string& comment : recording.comments) {
    if (comment.rfind(key + " ", 0) == 0) return comment.substr(key.size() + 1);
  }
  return {};
}

std::optional<RecordingFile> read_recording(const std::string& command, const std::string& path,
                                            const std::string& family_given, int& exit_code) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    fmt::print(stderr, "{}: cannot open {}\n", command, path);
    exit_code = exit_io;
    return std::nullopt;
  }
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  auto recording = record::read_serial_pcapng(bytes);
  if (!recording) {
    fmt::print(stderr, "{}: {}: {}\n", command, path, recording.error().message);
    exit_code = exit_bad_input;
    return std::nullopt;
  }
  const std::string name = family_given.empty() ? comment_value(*recording, "family") : family_given;
  const CliFamily* family = find_cli_family(name);
  if (family == nullptr) {
    fmt::print(stderr, "{}: {}: {}; give --family {}\n", command, path,
               name.empty() ? "the recording names no family" : "no family '" + name + "' in this build",
               cli_family_names("|"));
    exit_code = exit_usage;
    return std::nullopt;
  }
  return RecordingFile{std::move(*recording), family};
}

}  // namespace rangekit::cli
