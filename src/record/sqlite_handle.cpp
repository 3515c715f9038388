#include "sqlite_handle.hpp"

#include <optional>
#include <string>
#include <string_view>

#include "rangekit/core/text.hpp"
#include "rangekit/record/capture.hpp"

namespace rangekit::record {

Error sqlite_error(const std::string& path, sqlite3* database, int code, const std::string& what) {
  const int primary = code & 0xff;
  const std::string detail = database != nullptr ? sqlite3_errmsg(database) : sqlite3_errstr(code);
  if (primary == SQLITE_FULL) {
    return make_error(Errc::io, "capture " + path + ": disk full while " + what + " (" + detail +
                                    "); every batch committed before is kept");
  }
  if (primary == SQLITE_NOTADB || primary == SQLITE_CORRUPT) {
    return make_error(Errc::io, "capture " + path + ": not a rangekit capture or corrupt (" + detail + ")");
  }
  return make_error(Errc::io, "capture " + path + ": " + what + " failed (" + detail + ")");
}

Status execute(const std::string& path, sqlite3* database, const char* sql) {
  char* message = nullptr;
  const int code = sqlite3_exec(database, sql, nullptr, nullptr, &message);
  sqlite3_free(message);
  if (code != SQLITE_OK) return sqlite_error(path, database, code, std::string("running \"") + sql + "\"");
  return ok_status();
}

Result<Statement> prepare(const std::string& path, sqlite3* database, const char* sql) {
  sqlite3_stmt* raw = nullptr;
  const int code = sqlite3_prepare_v3(database, sql, -1, SQLITE_PREPARE_PERSISTENT, &raw, nullptr);
  Statement statement(raw);
  if (code != SQLITE_OK) return sqlite_error(path, database, code, std::string("preparing \"") + sql + "\"");
  return statement;
}

Result<bool> has_column(const std::string& path, sqlite3* database, const char* table, const char* column) {
  auto query = prepare(path, database, "SELECT count(*) FROM pragma_table_info(?1) WHERE name = ?2");
  if (!query) return std::move(query).error();
  sqlite3_bind_text(query->get(), 1, table, -1, SQLITE_STATIC);
  sqlite3_bind_text(query->get(), 2, column, -1, SQLITE_STATIC);
  const int code = sqlite3_step(query->get());
  if (code != SQLITE_ROW) return sqlite_error(path, database, code, "reading the columns of " + std::string(table));
  return sqlite3_column_int64(query->get(), 0) > 0;
}

Status check_integrity(const std::string& path, sqlite3* database, const char* table) {
  const std::string pragma = table != nullptr ? std::string("PRAGMA quick_check(") + table + ")" : "PRAGMA quick_check";
  auto check = prepare(path, database, pragma.c_str());
  if (!check) return std::move(check).error();
  const int code = sqlite3_step(check->get());
  if (code != SQLITE_ROW) return sqlite_error(path, database, code, "checking the file");
  const auto* verdict = reinterpret_cast<const char*>(sqlite3_column_text(check->get(), 0));
  if (verdict == nullptr || std::string_view(verdict) != "ok") {
    return make_error(Errc::io, "capture " + path + ": corrupt (" + (verdict ? verdict : "?") + ")");
  }
  return ok_status();
}

namespace {

// Reads the schema; a text file or a damaged header fails here (SQLITE_NOTADB),
// a database of some other program is recognised by its missing meta row.
Status check_is_capture(const std::string& path, sqlite3* database, IntegrityCheck integrity) {
  auto tables = prepare(path, database, "SELECT count(*) FROM sqlite_master");
  if (!tables) return std::move(tables).error();
  const int code = sqlite3_step(tables->get());
  if (code != SQLITE_ROW) return sqlite_error(path, database, code, "reading the schema");
  const auto table_count = sqlite3_column_int64(tables->get(), 0);
  if (table_count == 0) return ok_status();  // empty database: becomes a capture

  if (integrity == IntegrityCheck::at_open) {
    if (auto checked = check_integrity(path, database); !checked) return checked;
  }

  const auto meta = [database](const char* key) -> std::optional<std::string> {
    sqlite3_stmt* raw = nullptr;
    const int prepared = sqlite3_prepare_v2(database, "SELECT value FROM meta WHERE key = ?1", -1, &raw, nullptr);
    Statement query(raw);
    if (prepared != SQLITE_OK) return std::nullopt;
    sqlite3_bind_text(query.get(), 1, key, -1, SQLITE_STATIC);
    if (sqlite3_step(query.get()) != SQLITE_ROW) return std::nullopt;
    const auto* value = reinterpret_cast<const char*>(sqlite3_column_text(query.get(), 0));
    if (value == nullptr) return std::nullopt;  // a NULL value, whatever the schema says
    return std::string(value, static_cast<std::size_t>(sqlite3_column_bytes(query.get(), 0)));
  };
  if (meta("format") != "rangekit-capture") {
    return make_error(Errc::io, "capture " + path + ": an SQLite database, but not a rangekit capture");
  }
  // A newer rangekit may store what this one would drop or misread: refuse to replay or
  // append rather than go on without notice. Every capture has written the row.
  const auto version = meta("format_version");
  if (version != "1" && version != "2" && version != "3" && version != "4") {
    return make_error(Errc::unsupported,
                      "capture " + path + ": format version " +
                          (version ? "'" + text::printable(*version, true, 40) + "'" : std::string("(none)")) +
                          " is not one this rangekit reads (1, 2, 3, 4); was it written by a newer rangekit?");
  }
  return ok_status();
}

}  // namespace

Result<Database> open_database(const std::string& path, bool writable, bool may_create, IntegrityCheck integrity) {
  int flags = writable ? SQLITE_OPEN_READWRITE : SQLITE_OPEN_READONLY;
  if (may_create) flags |= SQLITE_OPEN_CREATE;
  sqlite3* raw = nullptr;
  const int code = sqlite3_open_v2(path.c_str(), &raw, flags | SQLITE_OPEN_NOMUTEX, nullptr);
  Database database(raw);
  if (code != SQLITE_OK) {
    return make_error(Errc::io, "capture " + path + ": cannot open (" +
                                    (raw != nullptr ? sqlite3_errmsg(raw) : sqlite3_errstr(code)) + ")");
  }
  sqlite3_extended_result_codes(database.get(), 1);
  sqlite3_busy_timeout(database.get(), 5000);
  // No PRAGMA mmap_size: a mapped capture that another program truncates while it is read
  // kills the reader with SIGBUS, where read() gives SQLite an error it reports.
  if (auto checked = check_is_capture(path, database.get(), integrity); !checked) return std::move(checked).error();
  return database;
}

std::string column_text(sqlite3_stmt* statement, int column) {
  const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(statement, column));
  return text != nullptr ? std::string(text, static_cast<std::size_t>(sqlite3_column_bytes(statement, column)))
                         : std::string();
}

}  // namespace rangekit::record
