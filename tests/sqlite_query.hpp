// One SQLite query whose answer is a single value, as text: what a test asks of a capture file.
#pragma once

#include <sqlite3.h>

#include <string>

namespace sqlite_test {

// "<error>" when the file cannot be opened or the query gives no row; "<null>" for NULL.
inline std::string query(const std::string& path, const std::string& sql) {
  sqlite3* database = nullptr;
  std::string result = "<error>";
  if (sqlite3_open_v2(path.c_str(), &database, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* statement = nullptr;
    if (sqlite3_prepare_v2(database, sql.c_str(), -1, &statement, nullptr) == SQLITE_OK &&
        sqlite3_step(statement) == SQLITE_ROW) {
      const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(statement, 0));
      result = text != nullptr ? text : "<null>";
    }
    sqlite3_finalize(statement);
  }
  sqlite3_close(database);
  return result;
}

}  // namespace sqlite_test
