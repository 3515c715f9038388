#include "cli/stop_signals.hpp"

namespace rangekit::cli {
namespace {

std::atomic<bool> stop_signalled{false};
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");

extern "C" void on_stop_signal(int /*signal*/) { stop_signalled.store(true); }

}  // namespace

StopSignals::StopSignals() {
  stop_signalled.store(false);
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  // SA_RESTART: a write to a full stdout pipe the signal interrupts goes on instead of failing
  // with EINTR, which fmt::print would throw as an error; the commands poll the flag anyway.
  action.sa_flags = SA_RESTART;
  sigemptyset(&action.sa_mask);
  ::sigaction(SIGINT, &action, &previous_int_);
  ::sigaction(SIGTERM, &action, &previous_term_);
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  ::sigaction(SIGPIPE, &ignore, &previous_pipe_);
}

StopSignals::~StopSignals() {
  ::sigaction(SIGINT, &previous_int_, nullptr);
  ::sigaction(SIGTERM, &previous_term_, nullptr);
  ::sigaction(SIGPIPE, &previous_pipe_, nullptr);
}

const std::atomic<bool>& StopSignals::flag() const noexcept { return stop_signalled; }

}  // namespace rangekit::cli
