// A store-and-forward spool: readings wait here, on disk, until a historian or a broker has
// confirmed them. SQLite in WAL mode, one row per reading; it also keeps each sensor's last
// sequence, so sequences go on rising across restarts.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "rangekit/core/result.hpp"

struct sqlite3;

namespace rangekit::record {

// One spooled reading: its sensor, its sequence, its time and the line the historian takes.
struct SpoolRow {
  std::int64_t id = 0;  // the spool's own order; set by the spool
  std::string sensor;
  std::uint64_t seq = 0;
  std::int64_t time_ns = 0;
  std::string line;
};

struct SpoolStats {
  std::uint64_t rows = 0;           // waiting now
  std::uint64_t bytes = 0;          // their size as the spool counts it (see row_bytes)
  std::uint64_t dropped = 0;        // oldest rows dropped past the cap, since opened
  std::int64_t oldest_time_ns = 0;  // of the oldest waiting row; 0 when empty
};

class Spool {
 public:
  // Opens or creates the file; `max_bytes` caps the rows' size (past it the oldest go).
  static Result<std::unique_ptr<Spool>> open(const std::string& path, std::uint64_t max_bytes);
  ~Spool();
  Spool(const Spool&) = delete;
  Spool& operator=(const Spool&) = delete;

  // The next sequence of `sensor` (its last plus one; 1 for a sensor never seen). Kept on
  // disk with the rows that use it, in append().
  std::uint64_t next_seq(const std::string& sensor);
  // Stores the rows in one transaction, with each sensor's last sequence; then drops the
  // oldest rows while the spool is above its cap. Returns how many were dropped.
  Result<std::uint64_t> append(const std::vector<SpoolRow>& rows);
  // The oldest `max` rows after the row `after` (0: from the first), oldest first.
  Result<std::vector<SpoolRow>> oldest(std::size_t max, std::int64_t after = 0);
  // The historian confirmed every row up to and including `id`.
  Status remove_through(std::int64_t id);
  // The historian confirmed `rows`, the oldest waiting as oldest() gave them: as
  // remove_through(rows.back().id), but their sizes come from `rows`, not from a read of the file.
  Status remove(const std::vector<SpoolRow>& rows);
  [[nodiscard]] SpoolStats stats() const;

  // What one row counts toward the cap: its line and sensor plus SQLite's overhead.
  static std::uint64_t row_bytes(const SpoolRow& row) noexcept;

 private:
  struct Statements;  // prepared once at open, reused by every call (spool.cpp)

  Spool(sqlite3* db, std::uint64_t max_bytes);
  Status prepare();
  Status load();
  Status drop_over_cap(std::uint64_t& dropped);
  Status count_rows();
  // Inside a transaction: deletes the rows through `id`; `count` and `bytes` are what they
  // are expected to free, counted again from the file when the deletion freed another number.
  Status delete_through(std::int64_t id, std::uint64_t count, std::uint64_t bytes);

  mutable std::mutex mutex_;
  sqlite3* db_;
  std::unique_ptr<Statements> statements_;
  std::uint64_t max_bytes_;
  std::int64_t dropped_through_ = 0;  // the cap dropped every row up to this id
  std::map<std::string, std::uint64_t, std::less<>> last_seq_;
  SpoolStats stats_;
};

}  // namespace rangekit::record
