// The spool's SQLite file. WAL with synchronous=NORMAL: a committed row survives the
// service's crash (kill -9); only a power loss may take the last commits.
#include "rangekit/record/spool.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <initializer_list>
#include <string>
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

// A statement prepared to be kept and run many times.
Status spool_prepare(sqlite3* db, const char* sql, Statement& statement) {
  sqlite3_stmt* raw = nullptr;
  const int code = sqlite3_prepare_v3(db, sql, -1, SQLITE_PREPARE_PERSISTENT, &raw, nullptr);
  statement.reset(raw);
  if (code != SQLITE_OK) return spool_error(db, std::string("prepare ") + sql);
  return ok_status();
}

// One use of a prepared statement: reset (and its bindings cleared) when the use ends, so the
// next call runs it again without preparing it.
class SpoolStep {
 public:
  explicit SpoolStep(const Statement& statement) : statement_(statement.get()) {}
  ~SpoolStep() {
    sqlite3_reset(statement_);
    sqlite3_clear_bindings(statement_);
  }
  SpoolStep(const SpoolStep&) = delete;
  SpoolStep& operator=(const SpoolStep&) = delete;
  [[nodiscard]] sqlite3_stmt* get() const noexcept { return statement_; }

 private:
  sqlite3_stmt* statement_;
};

// A transaction rolled back unless committed.
class SpoolTransaction {
 public:
  SpoolTransaction(const Statement& begin, const Statement& rollback) : rollback_(rollback) {
    const SpoolStep step(begin);
    begun_ = sqlite3_step(step.get()) == SQLITE_DONE;
  }
  ~SpoolTransaction() {
    if (!begun_) return;
    const SpoolStep step(rollback_);
    (void)sqlite3_step(step.get());
  }
  SpoolTransaction(const SpoolTransaction&) = delete;
  SpoolTransaction& operator=(const SpoolTransaction&) = delete;
  [[nodiscard]] bool begun() const noexcept { return begun_; }
  Status commit(sqlite3* db, const Statement& commit) {
    const SpoolStep step(commit);
    if (sqlite3_step(step.get()) != SQLITE_DONE) return spool_error(db, "commit");
    begun_ = false;
    return ok_status();
  }

 private:
  const Statement& rollback_;
  bool begun_ = false;
};

}  // namespace

struct Spool::Statements {
  Statement begin;
  Statement commit;
  Statement rollback;
  Statement insert;
  Statement sequence;
  Statement oldest;
  Statement first_time;
  Statement drop_candidates;
  Statement size_through;
  Statement count;
  Statement remove;
};

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
  if (auto prepared = spool->prepare(); !prepared) return std::move(prepared).error();
  if (auto loaded = spool->load(); !loaded) return std::move(loaded).error();
  return spool;
}

Spool::Spool(sqlite3* db, std::uint64_t max_bytes)
    : db_(db), statements_(std::make_unique<Statements>()), max_bytes_(max_bytes) {}

Spool::~Spool() {
  statements_.reset();  // finalized first: SQLite closes no connection with statements open
  sqlite3_close(db_);
}

Status Spool::prepare() {
  Statements& s = *statements_;
  // The size of a row as row_bytes counts it, less the overhead.
  const std::string size = "length(CAST(line AS BLOB)) + length(CAST(sensor AS BLOB))";
  const std::string count = "SELECT count(*), coalesce(sum(" + size + "), 0) FROM spool";
  const std::string size_through = count + " WHERE id <= ?";
  const std::string drop_candidates = "SELECT id, " + size + " FROM spool ORDER BY id LIMIT 1000";
  for (const auto& [statement, sql] : std::initializer_list<std::pair<Statement*, const char*>>{
           {&s.begin, "BEGIN IMMEDIATE"},
           {&s.commit, "COMMIT"},
           {&s.rollback, "ROLLBACK"},
           {&s.insert, "INSERT INTO spool(sensor, seq, time_ns, line) VALUES(?, ?, ?, ?)"},
           {&s.sequence,
            "INSERT INTO sequences(sensor, last) VALUES(?, ?) "
            "ON CONFLICT(sensor) DO UPDATE SET last = max(last, excluded.last)"},
           {&s.oldest, "SELECT id, sensor, seq, time_ns, line FROM spool WHERE id > ? ORDER BY id LIMIT ?"},
           {&s.first_time, "SELECT time_ns FROM spool ORDER BY id LIMIT 1"},
           {&s.drop_candidates, drop_candidates.c_str()},
           {&s.size_through, size_through.c_str()},
           {&s.count, count.c_str()},
           {&s.remove, "DELETE FROM spool WHERE id <= ?"},
       }) {
    if (auto prepared = spool_prepare(db_, sql, *statement); !prepared) return prepared;
  }
  return ok_status();
}

Status Spool::load() {
  Statement sequences;
  if (auto prepared = spool_prepare(db_, "SELECT sensor, last FROM sequences", sequences); !prepared) return prepared;
  while (sqlite3_step(sequences.get()) == SQLITE_ROW) {
    last_seq_[column_text(sequences.get(), 0)] = static_cast<std::uint64_t>(sqlite3_column_int64(sequences.get(), 1));
  }
  return count_rows();
}

// Rows, bytes and the oldest time, counted from the file.
Status Spool::count_rows() {
  {
    const SpoolStep size(statements_->count);
    if (sqlite3_step(size.get()) != SQLITE_ROW) return spool_error(db_, "read size");
    stats_.rows = static_cast<std::uint64_t>(sqlite3_column_int64(size.get(), 0));
    stats_.bytes = static_cast<std::uint64_t>(sqlite3_column_int64(size.get(), 1)) + stats_.rows * row_overhead;
  }
  const SpoolStep first(statements_->first_time);
  stats_.oldest_time_ns = sqlite3_step(first.get()) == SQLITE_ROW ? sqlite3_column_int64(first.get(), 0) : 0;
  return ok_status();
}

std::uint64_t Spool::next_seq(const std::string& sensor) {
  const std::lock_guard lock(mutex_);
  return ++last_seq_[sensor];
}

Result<std::uint64_t> Spool::append(const std::vector<SpoolRow>& rows) {
  const std::lock_guard lock(mutex_);
  if (rows.empty()) return std::uint64_t{0};
  SpoolTransaction transaction(statements_->begin, statements_->rollback);
  if (!transaction.begun()) return spool_error(db_, "begin");
  std::map<std::string_view, std::uint64_t> newest;
  std::uint64_t bytes = 0;
  {
    const SpoolStep insert(statements_->insert);
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
  }
  {
    const SpoolStep sequence(statements_->sequence);
    for (const auto& [sensor, last] : newest) {
      sqlite3_bind_text(sequence.get(), 1, sensor.data(), static_cast<int>(sensor.size()), SQLITE_STATIC);
      sqlite3_bind_int64(sequence.get(), 2, static_cast<sqlite3_int64>(last));
      if (sqlite3_step(sequence.get()) != SQLITE_DONE) return spool_error(db_, "store sequence");
      sqlite3_reset(sequence.get());
    }
  }
  if (stats_.rows == 0) stats_.oldest_time_ns = rows.front().time_ns;
  stats_.rows += rows.size();
  stats_.bytes += bytes;
  std::uint64_t dropped = 0;
  if (stats_.bytes > max_bytes_) {
    if (auto cut = drop_over_cap(dropped); !cut) return std::move(cut).error();
  }
  if (auto committed = transaction.commit(db_, statements_->commit); !committed) return std::move(committed).error();
  return dropped;
}

// Inside a transaction: the oldest rows go until the rest fits under the cap; then the oldest
// time is read again.
Status Spool::drop_over_cap(std::uint64_t& dropped) {
  while (stats_.bytes > max_bytes_ && stats_.rows > 0) {
    std::int64_t through = -1;
    std::uint64_t freed = 0;
    std::uint64_t count = 0;
    {
      const SpoolStep oldest(statements_->drop_candidates);
      while (stats_.bytes - freed > max_bytes_ && sqlite3_step(oldest.get()) == SQLITE_ROW) {
        through = sqlite3_column_int64(oldest.get(), 0);
        freed += static_cast<std::uint64_t>(sqlite3_column_int64(oldest.get(), 1)) + row_overhead;
        ++count;
      }
    }
    if (through < 0) break;
    {
      const SpoolStep remove(statements_->remove);
      sqlite3_bind_int64(remove.get(), 1, through);
      if (sqlite3_step(remove.get()) != SQLITE_DONE) return spool_error(db_, "drop oldest");
    }
    dropped_through_ = std::max(dropped_through_, through);
    stats_.bytes -= freed;
    stats_.rows -= count;
    stats_.dropped += count;
    dropped += count;
  }
  const SpoolStep first(statements_->first_time);
  stats_.oldest_time_ns = sqlite3_step(first.get()) == SQLITE_ROW ? sqlite3_column_int64(first.get(), 0) : 0;
  return ok_status();
}

Result<std::vector<SpoolRow>> Spool::oldest(std::size_t max, std::int64_t after) {
  const std::lock_guard lock(mutex_);
  const SpoolStep select(statements_->oldest);
  sqlite3_bind_int64(select.get(), 1, after);
  sqlite3_bind_int64(select.get(), 2, static_cast<sqlite3_int64>(max));
  std::vector<SpoolRow> rows;
  rows.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(max, stats_.rows)));
  int step = SQLITE_ROW;
  while ((step = sqlite3_step(select.get())) == SQLITE_ROW) {
    SpoolRow& row = rows.emplace_back();
    row.id = sqlite3_column_int64(select.get(), 0);
    row.sensor = column_text(select.get(), 1);
    row.seq = static_cast<std::uint64_t>(sqlite3_column_int64(select.get(), 2));
    row.time_ns = sqlite3_column_int64(select.get(), 3);
    row.line = column_text(select.get(), 4);
  }
  if (step != SQLITE_DONE) return spool_error(db_, "read");
  return rows;
}

Status Spool::delete_through(std::int64_t id, std::uint64_t count, std::uint64_t bytes) {
  {
    const SpoolStep remove(statements_->remove);
    sqlite3_bind_int64(remove.get(), 1, id);
    if (sqlite3_step(remove.get()) != SQLITE_DONE) return spool_error(db_, "remove confirmed rows");
  }
  if (static_cast<std::uint64_t>(sqlite3_changes(db_)) != count) return count_rows();
  stats_.rows -= std::min(count, stats_.rows);
  stats_.bytes -= std::min(bytes, stats_.bytes);
  const SpoolStep first(statements_->first_time);
  stats_.oldest_time_ns = sqlite3_step(first.get()) == SQLITE_ROW ? sqlite3_column_int64(first.get(), 0) : 0;
  return ok_status();
}

Status Spool::remove_through(std::int64_t id) {
  const std::lock_guard lock(mutex_);
  SpoolTransaction transaction(statements_->begin, statements_->rollback);
  if (!transaction.begun()) return spool_error(db_, "begin");
  std::uint64_t count = 0;
  std::uint64_t bytes = 0;
  {
    const SpoolStep size(statements_->size_through);
    sqlite3_bind_int64(size.get(), 1, id);
    if (sqlite3_step(size.get()) != SQLITE_ROW) return spool_error(db_, "size of removed rows");
    count = static_cast<std::uint64_t>(sqlite3_column_int64(size.get(), 0));
    bytes = static_cast<std::uint64_t>(sqlite3_column_int64(size.get(), 1)) + count * row_overhead;
  }
  if (auto removed = delete_through(id, count, bytes); !removed) return removed;
  return transaction.commit(db_, statements_->commit);
}

Status Spool::remove(const std::vector<SpoolRow>& rows) {
  if (rows.empty()) return ok_status();
  const std::lock_guard lock(mutex_);
  SpoolTransaction transaction(statements_->begin, statements_->rollback);
  if (!transaction.begun()) return spool_error(db_, "begin");
  // Rows the cap dropped meanwhile were counted off then.
  std::uint64_t count = 0;
  std::uint64_t bytes = 0;
  for (const SpoolRow& row : rows) {
    if (row.id <= dropped_through_) continue;
    ++count;
    bytes += row_bytes(row);
  }
  if (auto removed = delete_through(rows.back().id, count, bytes); !removed) return removed;
  return transaction.commit(db_, statements_->commit);
}

SpoolStats Spool::stats() const {
  const std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace rangekit::record
