#pragma once
// The processes a test starts end with it. A test that ctest kills at its timeout, or that
// crashes, takes its emulators and services along instead of leaving them to hold ctest's
// output open, which would keep ctest waiting for ever.
#include <poll.h>
#include <sys/prctl.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <optional>

namespace rangekit::test {

// fork(), with the child killed when the test's thread that called this ends. Call it
// from the test's own thread: a helper thread that ends early would take the child along.
inline pid_t fork_child() {
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // the test died before the prctl: no signal would come
  }
  return pid;
}

// For its length, orphans below this process come to it rather than to init, so that the end
// of a grandchild whose parent died can be waited for with waitpid.
struct OrphanReaper {
  OrphanReaper() { ::prctl(PR_SET_CHILD_SUBREAPER, 1); }
  ~OrphanReaper() { ::prctl(PR_SET_CHILD_SUBREAPER, 0); }
  OrphanReaper(const OrphanReaper&) = delete;
  OrphanReaper& operator=(const OrphanReaper&) = delete;
};

// The wait status of `pid`, a child or an orphan come to an OrphanReaper, once it ended
// within `limit` (-1 when it is no child of this process); nothing while it still runs.
inline std::optional<int> waited_within(pid_t pid, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  int status = 0;
  while (true) {
    const pid_t got = ::waitpid(pid, &status, WNOHANG);
    if (got != 0) return got == pid ? status : -1;
    if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
    ::poll(nullptr, 0, 10);  // waitpid has no timeout: poll on nothing between checks
  }
}

inline bool reaped_within(pid_t pid, std::chrono::milliseconds limit) {
  const auto status = waited_within(pid, limit);
  return status.has_value() && *status != -1;
}

// Asks a child to end (SIGTERM) and waits for it; one still there after `grace` is killed
// (SIGKILL). Returns its wait status. Under ThreadSanitizer an emulator has been seen to
// never run its SIGTERM handler: that costs a test `grace`, not ctest's timeout.
inline int end_child(pid_t pid, std::chrono::milliseconds grace = std::chrono::seconds(10)) {
  ::kill(pid, SIGTERM);
  if (const auto status = waited_within(pid, grace)) return *status;
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

}  // namespace rangekit::test
