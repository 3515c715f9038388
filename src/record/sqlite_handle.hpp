// Small RAII holders for the SQLite C API, shared by the capture writer and the
// replay reader.
#pragma once

#include <sqlite3.h>

#include <memory>
#include <string>

#include "rangekit/core/result.hpp"

namespace rangekit::record {

struct DatabaseCloser {
  void operator()(sqlite3* database) const noexcept { sqlite3_close_v2(database); }
};
using Database = std::unique_ptr<sqlite3, DatabaseCloser>;

struct StatementFinalizer {
  void operator()(sqlite3_stmt* statement) const noexcept { sqlite3_finalize(statement); }
};
using Statement = std::unique_ptr<sqlite3_stmt, StatementFinalizer>;

// "capture FILE: <what> (<sqlite message>)", with disk-full spelled out.
Error sqlite_error(const std::string& path, sqlite3* database, int code, const std::string& what);

Status execute(const std::string& path, sqlite3* database, const char* sql);
Result<Statement> prepare(const std::string& path, sqlite3* database, const char* sql);

// A text column of the current row ("" for NULL), read whole, NUL bytes included.
std::string column_text(sqlite3_stmt* statement, int column);

// Whether `table` has a column named `column`.
Result<bool> has_column(const std::string& path, sqlite3* database, const char* table, const char* column);

// Whether open_database runs PRAGMA quick_check itself, or leaves it to the caller, who
// must run check_integrity and refuse the file when it fails (a bulk reader runs it on a
// second connection while it reads, and discards what it read when the check fails).
enum class IntegrityCheck { at_open, by_caller };

// Opens `path` and checks that it is a readable rangekit capture (or empty when
// `may_create`). Nothing is written. Read-only opens map the file (PRAGMA mmap_size)
// rather than copy its pages with read().
Result<Database> open_database(const std::string& path, bool writable, bool may_create,
                               IntegrityCheck integrity = IntegrityCheck::at_open);

// PRAGMA quick_check: "capture FILE: corrupt (...)" when the file is damaged; of one table
// and its indexes only when `table` is given (a constant name, not quoted).
Status check_integrity(const std::string& path, sqlite3* database, const char* table = nullptr);

}  // namespace rangekit::record
