// The direct reader of a capture's `samples` table: the table's b-tree read from the file
// (sqlite_pages) instead of through SQLite's row engine, which tops out well below what
// a bulk read into NumPy needs (docs/python.md). The format is untouched: the reader is
// used only when the file qualifies (samples_pages_root), otherwise SQLite reads it.
#pragma once

#include <sqlite3.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"

namespace rangekit::record {

// The root page of `samples` when the direct reader can read it in the read transaction
// open on `database`: the schema of `samples` is this version's (column places known), the
// text is UTF-8, and the write-ahead log is absent or empty (every committed row is in the
// main file, and the open read transaction keeps a checkpoint from changing it). Nothing
// (fall back to SQLite) otherwise.
Result<std::optional<std::uint32_t>> samples_pages_root(const std::string& path, sqlite3* database);

// Every row of `samples` (of `device` only, unless empty) in seq order, with the fields of
// CaptureFields::array filled exactly as the SQLite reader fills them; one Sample reused.
// A malformed page or record stops the read with an error naming it ("capture PATH:
// samples table: ..."), after the rows before it were handed over.
Status read_samples_pages(const std::string& path, std::uint32_t root, std::string_view device,
                          const std::function<void(std::int64_t seq, const Sample&)>& on_sample);

}  // namespace rangekit::record
