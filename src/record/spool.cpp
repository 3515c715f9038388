// The spool's SQLite file. WAL with synchronous=NORMAL: a committed row survives the
// service's crash (kill -9); only a power loss may take the last commits.
#include "rangekit/record/spool.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <utility>

#include "sqlite_handle.hpp"

namespace rangekit::record {
namespace {

// What SQLite keeps per row besides the text (rowid, seq, time, record header), roughly.
constexpr std::uint64_t row_overhead = 40;

Error spool_error(sqlite3* db, const std::string& what) {
  return make_error(Errc::io, "spool: " + what + ": " + sqlite3_errmsg(db));
}

Status spool_exec(sqlite3* db, const char* sql) {
  char* message = nullptr;
  if (sqlite3_exec(db, sql, nullptr, nullptr, &message) != SQLITE_OK) {
    std::string text = message != nullptr ? message : "unknown error";
    sqlite3_free(message);
    return make_error(Errc::io, std::string("spool: ") + sql + ": " + text);
  }
  return ok_status();
}

// A prepared statement, finalized when it goes.
class SpoolStatement {
 public:
  SpoolStatement(sqlite3* db, const char* sql) { sqlite3_prepare_v2(db, sql, -1, &statement_, nullptr); }
  ~SpoolStatement() { sqlite3_finalize(statement_); }
  SpoolStatement(const SpoolStatement&) = delete;
  SpoolStatement& operator=(const SpoolStatement&) = delete;
  [[nodiscard]] sqlite3_stmt* get() const noexcept { return statement_; }
  explicit operator bool() const noexcept { return statement_ != nullptr; }

 private:
  sqlite3_stmt* statement_ = nullptr;
};

// A transaction rolled back unless committed.
class SpoolTransaction {
 public:
  explicit SpoolTransaction(sqlite3* db) : db_(db), begun_(spool_exec(db, "BEGIN IMMEDIATE").ok()) {}
  ~SpoolTransaction() {
    if (begun_) (void)spool_exec(db_, "ROLLBACK");
  }
  SpoolTransaction(const SpoolTransaction&) = delete;
  SpoolTransaction& operator=(const SpoolTransaction&) = delete;
  [[nodiscard]] bool begun() const noexcept { return begun_; }
  Status commit() {
    begun_ = false;
    return spool_exec(db_, "COMMIT");
  }

 private:
  sqlite3* db_;
  bool begun_;
};

}  // namespace

std::uint64_t Spool::row_bytes(const SpoolRow& row) noexcept {
  return row.line.size() + row.sensor.size() + row_overhead;
}

Result<std::unique_ptr<Spool>> Spool::open(const std::string& path, std::uint64_t max_bytes) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX, nullptr) !=
      SQLITE_OK) {
    Error error = make_error(Errc::io, "spool " + path + ": " + (db != nullptr ? sqlite3_errmsg(db) : "cannot open"));
    sqlite3_close(db);
    return error;
  }
  std::unique_ptr<Spool> spool(new Spool(db, max_bytes));
  sqlite3_busy_timeout(db, 5000);
  for (const char* sql :
       {"PRAGMA journal_mode=WAL", "PRAGMA synchronous=NORMAL",
        "CREATE TABLE IF NOT EXISTS spool(id INTEGER PRIMARY KEY AUTOINCREMENT, sensor TEXT NOT NULL, "
        "seq INTEGER NOT NULL, time_ns INTEGER NOT NULL, line TEXT NOT NULL)",
        "CREATE TABLE IF NOT EXISTS sequences(sensor TEXT PRIMARY KEY, last INTEGER NOT NULL)"}) {
    if (auto done = spool_exec(db, sql); !done) {
      Error error = std::move(done).error();
      error.message = "spool " + path + ": " + error.message;
      return error;
    }
  }
  if (auto loaded = spool->load(); !loaded) return std::move(loaded).error();
  return spool;
}

Spool::Spool(sqlite3* db, std::uint64_t max_bytes) : db_(db), max_bytes_(max_bytes) {}

Spool::~Spool() { sqlite3_close(db_); }

Status Spool::load() {
  SpoolStatement sequences(db_, "SELECT sensor, last FROM sequences");
  if (!sequences) return spool_error(db_, "read sequences");
  while (sqlite3_step(sequences.get()) == SQLITE_ROW) {
    last_seq_[column_text(sequences.get(), 0)] = static_cast<std::uint64_t>(sqlite3_column_int64(sequences.get(), 1));
  }
  SpoolStatement size(db_,
                      "SELECT count(*), coalesce(sum(length(CAST(line AS BLOB)) + length(CAST(sensor AS BLOB))), 0), "
                      "coalesce((SELECT time_ns FROM spool ORDER BY id LIMIT 1), 0) FROM spool");
  if (!size || sqlite3_step(size.get()) != SQLITE_ROW) return spool_error(db_, "read size");
  stats_.rows = static_cast<std::uint64_t>(sqlite3_column_int64(size.get(), 0));
  stats_.bytes = static_cast<std::uint64_t>(sqlite3_column_int64(size.get(), 1)) + stats_.rows * row_overhead;
  stats_.oldest_time_ns = sqlite3_column_int64(size.get(), 2);
  return ok_status();
}

std::uint64_t Spool::next_seq(const std::string& sensor) {
  const std::lock_guard lock(mutex_);
  return ++last_seq_[sensor];
}

Result<std::uint64_t> Spool::append(const std::vector<SpoolRow>& rows) {
  const std::lock_guard lock(mutex_);
  if (rows.empty()) return std::uint64_t{0};
  SpoolTransaction transaction(db_);
  if (!transaction.begun()) return spool_error(db_, "begin");
  SpoolStatement insert(db_, "INSERT INTO spool(sensor, seq, time_ns, line) VALUES(?, ?, ?, ?)");
  if (!insert) return spool_error(db_, "prepare insert");
  std::map<std::string_view, std::uint64_t> newest;
  std::uint64_t bytes = 0;
  for (const SpoolRow& row : rows) {
    sqlite3_bind_text(insert.get(), 1, row.sensor.data(), static_cast<int>(row.sensor.size()), SQLITE_STATIC);
    sqlite3_bind_int64(insert.get(), 2, static_cast<sqlite3_int64>(row.seq));
    sqlite3_bind_int64(insert.get(), 3, row.time_ns);
    sqlite3_bind_text(insert.get(), 4, row.line.data(), static_cast<int>(row.line.size()), SQLITE_STATIC);
    if (sqlite3_step(insert.get()) != SQLITE_DONE) return spool_error(db_, "insert");
    sqlite3_reset(insert.get());
    auto& last = newest[row.sensor];
    last = std::max(last, row.seq);
    bytes += row_bytes(row);
  }
  SpoolStatement sequence(db_,
                          "INSERT INTO sequences(sensor, last) VALUES(?, ?) "
                          "ON CONFLICT(sensor) DO UPDATE SET last = max(last, excluded.last)");
  if (!sequence) return spool_error(db_, "prepare sequence");
  for (const auto& [sensor, last] : newest) {
    sqlite3_bind_text(sequence.get(), 1, sensor.data(), static_cast<int>(sensor.size()), SQLITE_STATIC);
    sqlite3_bind_int64(sequence.get(), 2, static_cast<sqlite3_int64>(last));
    if (sqlite3_step(sequence.get()) != SQLITE_DONE) return spool_error(db_, "store sequence");
    sqlite3_reset(sequence.get());
  }
  if (stats_.rows == 0) stats_.oldest_time_ns = rows.front().time_ns;
  stats_.rows += rows.size();
  stats_.bytes += bytes;
  std::uint64_t dropped = 0;
  if (auto cut = drop_over_cap(dropped); !cut) return std::move(cut).error();
  if (auto committed = transaction.commit(); !committed) return std::move(committed).error();
  return dropped;
}

// Inside append's transaction: the oldest rows go until the rest fits under the cap.
Status Spool::drop_over_cap(std::uint64_t& dropped) {
  while (stats_.bytes > max_bytes_ && stats_.rows > 0) {
    SpoolStatement oldest(db_,
                          "SELECT id, length(CAST(line AS BLOB)) + length(CAST(sensor AS BLOB)) FROM spool "
                          "ORDER BY id LIMIT 1000");
    if (!oldest) return spool_error(db_, "prepare drop");
    std::int64_t through = -1;
    std::uint64_t freed = 0;
    std::uint64_t count = 0;
    while (stats_.bytes - freed > max_bytes_ && sqlite3_step(oldest.get()) == SQLITE_ROW) {
      through = sqlite3_column_int64(oldest.get(), 0);
      freed += static_cast<std::uint64_t>(sqlite3_column_int64(oldest.get(), 1)) + row_overhead;
      ++count;
    }
    if (through < 0) break;
    SpoolStatement remove(db_, "DELETE FROM spool WHERE id <= ?");
    sqlite3_bind_int64(remove.get(), 1, through);
    if (sqlite3_step(remove.get()) != SQLITE_DONE) return spool_error(db_, "drop oldest");
    stats_.bytes -= freed;
    stats_.rows -= count;
    stats_.dropped += count;
    dropped += count;
  }
  SpoolStatement first(db_, "SELECT time_ns FROM spool ORDER BY id LIMIT 1");
  stats_.oldest_time_ns = first && sqlite3_step(first.get()) == SQLITE_ROW ? sqlite3_column_int64(first.get(), 0) : 0;
  return ok_status();
}

Result<std::vector<SpoolRow>> Spool::oldest(std::size_t max, std::int64_t after) {
  const std::lock_guard lock(mutex_);
  SpoolStatement select(db_, "SELECT id, sensor, seq, time_ns, line FROM spool WHERE id > ? ORDER BY id LIMIT ?");
  if (!select) return spool_error(db_, "prepare read");
  sqlite3_bind_int64(select.get(), 1, after);
  sqlite3_bind_int64(select.get(), 2, static_cast<sqlite3_int64>(max));
  std::vector<SpoolRow> rows;
  int step = SQLITE_ROW;
  while ((step = sqlite3_step(select.get())) == SQLITE_ROW) {
    SpoolRow row;
    row.id = sqlite3_column_int64(select.get(), 0);
    row.sensor = column_text(select.get(), 1);
    row.seq = static_cast<std::uint64_t>(sqlite3_column_int64(select.get(), 2));
    row.time_ns = sqlite3_column_int64(select.get(), 3);
    row.line = column_text(select.get(), 4);
    rows.push_back(std::move(row));
  }
  if (step != SQLITE_DONE) return spool_error(db_, "read");
  return rows;
}

Status Spool::remove_through(std::int64_t id) {
  const std::lock_guard lock(mutex_);
  SpoolTransaction transaction(db_);
  if (!transaction.begun()) return spool_error(db_, "begin");
  SpoolStatement size(db_,
                      "SELECT count(*), coalesce(sum(length(CAST(line AS BLOB)) + length(CAST(sensor AS BLOB))), 0) "
                      "FROM spool WHERE id <= ?");
  if (!size) return spool_error(db_, "prepare remove");
  sqlite3_bind_int64(size.get(), 1, id);
  if (sqlite3_step(size.get()) != SQLITE_ROW) return spool_error(db_, "size of removed rows");
  const auto count = static_cast<std::uint64_t>(sqlite3_column_int64(size.get(), 0));
  const auto bytes = static_cast<std::uint64_t>(sqlite3_column_int64(size.get(), 1)) + count * row_overhead;
  SpoolStatement remove(db_, "DELETE FROM spool WHERE id <= ?");
  sqlite3_bind_int64(remove.get(), 1, id);
  if (sqlite3_step(remove.get()) != SQLITE_DONE) return spool_error(db_, "remove confirmed rows");
  std::uint64_t none = 0;
  stats_.rows -= std::min(count, stats_.rows);
  stats_.bytes -= std::min(bytes, stats_.bytes);
  if (auto refreshed = drop_over_cap(none); !refreshed) return refreshed;  // refreshes the oldest time
  return transaction.commit();
}

SpoolStats Spool::stats() const {
  const std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace rangekit::record
