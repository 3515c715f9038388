// The SQLite replay reader on arbitrary files: open_replay either refuses the file with
// a message or streams items until it finishes, whatever the bytes (a damaged page, a
// schema of another program, NULLs where the capture writes values, a foreign format_version).
// The input is one file in a private temporary directory (tmpfs where there is one).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "rangekit/record/replay.hpp"

namespace {

std::string file_path() {
  const char* base = ::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
  static const std::string path = std::string(base) + "/rangekit-replay-fuzz-" + std::to_string(::getpid()) + ".sqlite";
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = file_path();
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, file) != size) std::abort();
  std::fclose(file);
  {
    auto source = rangekit::record::open_replay(path, rangekit::record::ReplayOptions{0.0, {}});
    if (!source) {
      if (source.error().message.empty()) std::abort();
    } else {
      // Every row comes out once and the source then says it is finished.
      for (int items = 0; items < 100000; ++items) {
        if (!(*source)->next(std::chrono::milliseconds(0))) break;
      }
      if (!(*source)->finished()) std::abort();
    }
  }
  std::remove(path.c_str());
  std::remove((path + "-wal").c_str());
  std::remove((path + "-shm").c_str());
  return 0;
}
