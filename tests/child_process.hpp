#pragma once
// The processes a test starts end with it. A test that ctest kills at its timeout, or that
// crashes, takes its emulators and services along instead of leaving them to hold ctest's
// output open, which would keep ctest waiting for ever.
#include <sys/prctl.h>
#include <sys/types.h>
#include <unistd.h>
#include <csignal>

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

}  // namespace rangekit::test
