// A tap's recording read for a command (sim replay, tap compare): the pcapng file, checked
// whole, and the family it is of, from its `family` comment or the command line.
#pragma once

#include <optional>
#include <string>

#include "cli/cli_family.hpp"
#include "rangekit/record/pcapng.hpp"

namespace rangekit::cli {

struct RecordingFile {
  record::SerialRecording recording;
  const CliFamily* family = nullptr;
};

// The value of the first section comment "<key> <value>" ("family uls", "line 115200 8N1").
std::string comment_value(const record::SerialRecording& recording, const std::string& key);

// The recording and its family; none when it cannot be had: the reason is printed as
// "<command>: ..." and `exit_code` set (4 unreadable, 3 damaged, 2 no family).
std::optional<RecordingFile> read_recording(const std::string& command, const std::string& path,
                                            const std::string& family_given, int& exit_code);

}  // namespace rangekit::cli
