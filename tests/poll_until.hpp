// For a condition nothing can be waited on for (a counter of another process or thread, a file
// another process makes): looks again every 20 ms until it holds or the limit passes.
#pragma once

#include <chrono>
#include <filesystem>
#include <thread>

namespace rangekit::test {

template <class Done>
bool poll_until(std::chrono::milliseconds limit, Done&& done) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // between looks, not a synchronisation
  }
  return true;
}

// A path another process makes (a tap's or an emulator's pty link) is there.
inline bool path_appears(const std::filesystem::path& path,
                         std::chrono::milliseconds limit = std::chrono::seconds(20)) {
  return poll_until(limit, [&] { return std::filesystem::exists(path); });
}

}  // namespace rangekit::test
