// SIGINT/SIGTERM for a command that runs until stopped (stream, capture, serve):
// they set a flag the command polls; SIGPIPE is ignored so that a reader going
// away (`| head`) is a write error instead of killing the process before its
// files are closed. Installed for the life of one object, then restored.
#pragma once

#include <atomic>
#include <csignal>

namespace rangekit::cli {

class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  [[nodiscard]] const std::atomic<bool>& flag() const noexcept;
  [[nodiscard]] bool stopped() const noexcept { return flag().load(); }

 private:
  struct sigaction previous_int_ {};
  struct sigaction previous_term_ {};
  struct sigaction previous_pipe_ {};
};

}  // namespace rangekit::cli
