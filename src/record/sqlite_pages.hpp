// A read-only walker of one table b-tree in the SQLite file format
// (https://www.sqlite.org/fileformat2.html): the database header, table interior (0x05)
// and leaf (0x0D) pages, cells, varints and overflow chains. It hands over each row's
// rowid and record bytes in key order and knows nothing of what the columns mean.
// Every malformed structure (page type, cell outside its page, varint past the end, page
// number beyond the file, a page reached twice) is an Errc::io naming it, never a crash or
// a hang: each page is visited at most once.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rangekit/core/result.hpp"

namespace rangekit::record::sqlite_pages {

// What the 100-byte database header says about the pages.
struct Geometry {
  std::uint32_t page_size = 0;
  std::uint32_t usable_size = 0;    // page size less the reserved bytes at each page's end
  std::uint32_t page_count = 0;     // pages present in the file (header count, bounded by the file size)
  std::uint32_t text_encoding = 0;  // 1 UTF-8, 2 UTF-16le, 3 UTF-16be
};

// The header of a file of `file_size` bytes whose first bytes are `start` (at least 100).
Result<Geometry> parse_header(std::span<const std::uint8_t> start, std::uint64_t file_size);

// Where the walker's pages come from: a file or, for tests and the fuzzer, memory.
class PageSource {
 public:
  virtual ~PageSource() = default;
  [[nodiscard]] virtual const Geometry& geometry() const = 0;
  // Copies page `number` (1-based, within page_count) into `into` (page_size bytes).
  virtual Status read(std::uint32_t number, std::span<std::uint8_t> into) = 0;
};

// Pages of a file read with pread() a megabyte at a time (no mmap: a file truncated while
// it is read gives an error, not SIGBUS).
Result<std::unique_ptr<PageSource>> open_file_pages(const std::string& path);
// Pages of bytes in memory (not copied: they must outlive the source).
Result<std::unique_ptr<PageSource>> memory_pages(std::span<const std::uint8_t> bytes);

// Called for each row in rowid order with the record's bytes (valid during the call only);
// returns false to stop the walk.
using RowVisitor = std::function<bool(std::int64_t rowid, std::span<const std::uint8_t> record)>;

// Walks the table b-tree rooted at page `root`. Rows whose record spills into overflow
// pages are reassembled. A malformed structure stops the walk with an error naming the
// page; the rows before it have been handed over.
Status walk_table(PageSource& pages, std::uint32_t root, const RowVisitor& visit);

}  // namespace rangekit::record::sqlite_pages
