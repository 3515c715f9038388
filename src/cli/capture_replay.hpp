// `rangekit sim replay CAPTURE`: a sensor of a `rangekit capture` file acted out by its
// family's emulator, whose target follows the captured readings at their recorded pace.
// A capture keeps readings, not the conversation, so the host talks to the emulator as to
// any; what it streams is what was captured.
#pragma once

#include <string>

namespace rangekit::cli {

// Whether the file begins as an SQLite database does (a capture), rather than as a pcapng.
bool is_capture_file(const std::string& path);

struct CaptureReplayOptions {
  std::string file;
  std::string port;
  std::string family;  // empty: the first captured sample's
  std::string source;  // empty: the first captured sample's port or endpoint
};

// Runs until Ctrl-C; an exit code.
int run_capture_replay(const CaptureReplayOptions& options);

}  // namespace rangekit::cli
