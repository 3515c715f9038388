// The direct page reader of captures (src/record/sqlite_pages, sqlite_record) on arbitrary
// bytes taken as an SQLite file: the header is parsed, the table b-trees rooted at the first
// pages walked and every record decoded. Whatever the bytes, each walk ends with rows in
// increasing rowid order and either success or an error, never a crash, a hang or a read
// outside the buffer (ASan). The seeds are small SQLite files (page size 512) holding a
// capture's samples table: interior pages, overflow chains, deleted rows.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "record/sqlite_pages.hpp"
#include "record/sqlite_record.hpp"

using namespace rangekit::record::sqlite_pages;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto pages = memory_pages(std::span<const std::uint8_t>(data, size));
  if (!pages.ok()) return 0;
  const std::uint32_t last_root = std::min<std::uint32_t>((*pages)->geometry().page_count, 8);
  for (std::uint32_t root = 1; root <= last_root; ++root) {
    std::array<FieldValue, 20> fields{};
    std::int64_t previous = 0;
    bool first = true;
    std::size_t text_bytes = 0;
    const auto walked = walk_table(**pages, root, [&](std::int64_t rowid, std::span<const std::uint8_t> record) {
      if (!first && rowid <= previous) std::abort();  // the walker promises key order
      first = false;
      previous = rowid;
      if (decode_record(record, fields)) {
        for (const FieldValue& field : fields) {
          for (const char byte : field.bytes) text_bytes += static_cast<unsigned char>(byte) & 1U;
        }
      }
      return true;
    });
    if (!walked.ok() && walked.error().message.empty()) std::abort();  // errors say what
    (void)text_bytes;
  }
  return 0;
}
