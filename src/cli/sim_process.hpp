// An emulator started as a child process (`rangekit sim ...`, by default from this
// same binary), for `rangekit demo` and the streaming bench: waits for its ready
// line instead of sleeping and stops it (SIGTERM, then SIGKILL) when destroyed.
// The child runs in its own process group (Ctrl-C goes to the parent, which stops
// it) and gets SIGTERM if the parent dies without stopping it, or rather when the
// thread that called start() ends: call it from one that outlives the child.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

#include "rangekit/core/result.hpp"

namespace rangekit::cli {

class SimProcess {
 public:
  // Runs `<executable> sim <arguments...>` and waits up to `timeout` for the
  // line containing "ready:". Its stderr is kept in `log_path` for messages.
  // The executable is this binary unless another program names the CLI's path.
  static Result<SimProcess> start(const std::vector<std::string>& arguments, const std::string& log_path,
                                  std::chrono::milliseconds timeout, const std::string& executable = "/proc/self/exe");

  SimProcess(SimProcess&& other) noexcept;
  SimProcess& operator=(SimProcess&& other) noexcept;
  SimProcess(const SimProcess&) = delete;
  SimProcess& operator=(const SimProcess&) = delete;
  ~SimProcess();

  [[nodiscard]] const std::string& ready_line() const { return ready_line_; }
  [[nodiscard]] pid_t pid() const { return pid_; }
  // Sends SIGTERM and waits (SIGKILL after two seconds). Safe to call twice.
  void stop() noexcept;

 private:
  SimProcess(pid_t pid, std::string ready_line) : pid_(pid), ready_line_(std::move(ready_line)) {}
  pid_t pid_ = -1;
  std::string ready_line_;
};

}  // namespace rangekit::cli
