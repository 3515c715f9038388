// A serial recording's bytes, as a file on disk can hold them after a crash, a copy cut short
// or a hostile hand: read as pcapng, never more chunk bytes than the file holds, no crash.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "rangekit/record/pcapng.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view file(reinterpret_cast<const char*>(data), size);
  const auto read = rangekit::record::read_serial_pcapng(file);
  if (read) {
    std::size_t bytes = 0;
    for (const auto& chunk : read->chunks) bytes += chunk.bytes.size();
    if (bytes > size) std::abort();
  }
  return 0;
}
