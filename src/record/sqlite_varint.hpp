// SQLite's varint (https://www.sqlite.org/fileformat2.html, "varint"): 1-9 bytes, big-endian,
// seven bits a byte with the high bit saying more follow, the ninth byte whole. Shared by
// the page walker (cell sizes, row ids) and the record decoder (serial types).
#pragma once

#include <cstddef>
#include <cstdint>

namespace rangekit::record::sqlite_pages {

// A varint at `offset` of `bytes[0, end)`, `offset` moved past it; false when it runs past
// `end`. One-byte varints (serial types below 128: nearly every value of a capture) take
// the inlined first test.
inline bool read_varint(const std::uint8_t* bytes, std::size_t end, std::size_t& offset, std::uint64_t& value) {
  if (offset < end && bytes[offset] < 0x80U) {
    value = bytes[offset++];
    return true;
  }
  value = 0;
  for (int i = 0; i < 8; ++i) {
    if (offset >= end) return false;
    const std::uint8_t byte = bytes[offset++];
    value = (value << 7U) | (byte & 0x7FU);
    if ((byte & 0x80U) == 0) return true;
  }
  if (offset >= end) return false;
  value = (value << 8U) | bytes[offset++];
  return true;
}

}  // namespace rangekit::record::sqlite_pages
