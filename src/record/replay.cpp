#include "rangekit/record/replay.hpp"

#include <algorithm>
#include <condition_variable>
#include <functional>
#include <future>
#include <mutex>
#include <utility>

#include "capture_columns.hpp"
#include "capture_pages.hpp"
#include "names.hpp"
#include "sqlite_handle.hpp"
#include "targets_text.hpp"

namespace rangekit::record {
namespace {

using SystemTime = std::chrono::system_clock::time_point;

// The samples' columns in the layout's order (capture_columns.hpp): a column the file lacks (a
// capture of an older version) reads as NULL, and so does one an array read leaves out: SQLite
// then never decodes it (a bulk scan spends most of its time decoding columns).
Result<std::string> samples_sql(const std::string& path, sqlite3* database, bool array) {
  const CaptureLayout& layout = capture_layout();
  std::string sql =
      array ? "SELECT seq, time_ns, device, NULL, address, kind" : "SELECT seq, time_ns, device, source, address, kind";
  const auto add = [&](std::string_view name, bool read) -> Status {
    const std::string column(name);
    auto present = has_column(path, database, "samples", column.c_str());
    if (!present) return std::move(present).error();
    sql += ", " + (*present && read ? column : std::string("NULL"));
    return ok_status();
  };
  for (const ChannelColumn& column : layout.channels) {
    if (auto status = add(column.name, !array || column.in_stream); !status) return status.error();
  }
  if (auto status = add("suspect", true); !status) return status.error();
  if (auto status = add("suspect_reason", !array); !status) return status.error();
  return sql + " FROM samples ORDER BY seq";
}
constexpr const char* events_sql = "SELECT seq, time_ns, kind, message, count FROM events ORDER BY seq";

SystemTime from_nanos(std::int64_t nanos) {
  return SystemTime(std::chrono::duration_cast<SystemTime::duration>(std::chrono::nanoseconds(nanos)));
}

std::string_view column_view(sqlite3_stmt* statement, int column) {
  const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(statement, column));
  return text != nullptr ? std::string_view(text, static_cast<std::size_t>(sqlite3_column_bytes(statement, column)))
                         : std::string_view();
}

// One column of the current row: its type asked once, then its value by that type
// (a scan of millions of rows spends its time in these calls).
class Column {
 public:
  Column(sqlite3_stmt* row, int index) : value_(sqlite3_column_value(row, index)), type_(sqlite3_value_type(value_)) {}
  [[nodiscard]] bool is_null() const { return type_ == SQLITE_NULL; }
  template <class T>
  [[nodiscard]] std::optional<T> integer() const {
    if (is_null()) return std::nullopt;
    return static_cast<T>(sqlite3_value_int64(value_));
  }
  [[nodiscard]] std::optional<double> real() const {
    if (is_null()) return std::nullopt;
    return sqlite3_value_double(value_);
  }
  // The text (empty when NULL); valid until the row changes.
  [[nodiscard]] std::string_view text() const {
    if (is_null()) return {};
    const auto* text = reinterpret_cast<const char*>(sqlite3_value_text(value_));
    return text != nullptr ? std::string_view(text, static_cast<std::size_t>(sqlite3_value_bytes(value_)))
                           : std::string_view();
  }

 private:
  sqlite3_value* value_;
  int type_;
};

// A row's columns by place, as read_channels reads them.
class SqliteRow {
 public:
  explicit SqliteRow(sqlite3_stmt* row) : row_(row) {}
  [[nodiscard]] bool is_null(std::size_t index) const { return Column(row_, static_cast<int>(index)).is_null(); }
  [[nodiscard]] std::optional<std::int64_t> integer(std::size_t index) const {
    return Column(row_, static_cast<int>(index)).integer<std::int64_t>();
  }
  [[nodiscard]] std::optional<double> real(std::size_t index) const {
    return Column(row_, static_cast<int>(index)).real();
  }
  [[nodiscard]] std::string_view text(std::size_t index) const { return Column(row_, static_cast<int>(index)).text(); }

 private:
  sqlite3_stmt* row_;
};

// The places in samples_sql's rows.
constexpr int first_channel_in_row = 6;

// Fills `sample` from a row, reusing its strings' and targets' storage: a scan of
// millions of rows allocates nothing per row. Every field of Sample is assigned here, for
// every row (a field added to Sample must be too): nothing of the previous row stays, and
// the sample is not rebuilt nor its strings moved out and back for each row.
void read_sample_into(sqlite3_stmt* row, Sample& sample) {
  const auto column = [row](int index) { return Column(row, index); };
  sample.time = from_nanos(sqlite3_column_int64(row, 1));
  sample.device.assign(column(2).text());
  // Rows of one source follow each other: the previous row's name is kept, not made again.
  if (const std::string_view text = column(3).text(); sample.source != text) sample.source = SharedName(text);
  sample.address = column(4).integer<int>().value_or(-1);
  const CaptureLayout& layout = capture_layout();
  const FamilyColumns* columns = layout.columns_of(sample.device);
  sample.kind = SampleKind{};
  if (columns != nullptr) {
    sample.kind = find_kind(*columns->family, column(5).text()).value_or(SampleKind{});
    SqliteRow values(row);
    read_channels(values, first_channel_in_row, *columns, sample, false);
  } else {
    sample.values.clear();
    sample.targets.clear();
  }
  const int suspect = first_channel_in_row + static_cast<int>(layout.channels.size());
  sample.suspect = column(suspect).integer<int>().value_or(0) != 0;
  sample.suspect_reason.clear();
  if (sample.suspect) sample.suspect_reason.assign(column(suspect + 1).text());
}

// The device column of a row, without copying it.
std::string_view row_device(sqlite3_stmt* row) { return column_view(row, 2); }

StreamEvent read_event(sqlite3_stmt* row) {
  StreamEvent event;
  event.time = from_nanos(sqlite3_column_int64(row, 1));
  event.kind = parse_stream_event_kind(column_text(row, 2)).value_or(StreamEventKind::bad_frame);
  event.message = column_text(row, 3);
  event.count = static_cast<std::uint64_t>(sqlite3_column_int64(row, 4));
  return event;
}

// One ordered table read row by row, with the next row's sequence number at hand.
class Cursor {
 public:
  explicit Cursor(Statement statement) : statement_(std::move(statement)) {}

  // Steps to the next row; false at the end or on a read error (kept in error()).
  bool advance() {
    const int code = sqlite3_step(statement_.get());
    has_row_ = code == SQLITE_ROW;
    if (code != SQLITE_ROW && code != SQLITE_DONE) failed_code_ = code;
    return has_row_;
  }
  [[nodiscard]] bool has_row() const { return has_row_; }
  [[nodiscard]] std::int64_t seq() const { return sqlite3_column_int64(statement_.get(), 0); }
  [[nodiscard]] sqlite3_stmt* row() const { return statement_.get(); }
  [[nodiscard]] int failed_code() const { return failed_code_; }

 private:
  Statement statement_;
  bool has_row_ = false;
  int failed_code_ = 0;
};

// A capture's two tables, open for reading in seq order.
struct CaptureCursors {
  Database database;
  Cursor samples;
  Cursor events;
};

Result<CaptureCursors> open_cursors(const std::string& path, IntegrityCheck integrity = IntegrityCheck::at_open,
                                    CaptureFields fields = CaptureFields::all) {
  auto database = open_database(path, false, false, integrity);
  if (!database) return std::move(database).error();
  auto sql = samples_sql(path, database->get(), fields == CaptureFields::array);
  if (!sql) return std::move(sql).error();
  auto samples = prepare(path, database->get(), sql->c_str());
  if (!samples) return make_error(Errc::io, "capture " + path + ": no samples table, not a rangekit capture");
  auto events = prepare(path, database->get(), events_sql);
  if (!events) return make_error(Errc::io, "capture " + path + ": no events table, not a rangekit capture");
  return CaptureCursors{std::move(*database), Cursor(std::move(*samples)), Cursor(std::move(*events))};
}

// A capture damaged after it was opened ends its reading with one event saying why.
StreamEvent read_error_event(const std::string& path, sqlite3* database, int code) {
  StreamEvent event;
  event.time = std::chrono::system_clock::now();
  event.kind = StreamEventKind::bad_frame;
  event.message = sqlite_error(path, database, code, "reading").message;
  return event;
}

class ReplaySource final : public SampleSource {
 public:
  ReplaySource(std::string path, CaptureCursors cursors, ReplayOptions options)
      : path_(std::move(path)),
        database_(std::move(cursors.database)),
        samples_(std::move(cursors.samples)),
        events_(std::move(cursors.events)),
        options_(std::move(options)) {
    samples_.advance();
    events_.advance();
    load_next();
  }

  std::optional<StreamItem> next(std::chrono::milliseconds timeout) override {
    std::unique_lock lock(mutex_);
    if (stopped_ || !pending_) return std::nullopt;
    if (options_.speed > 0) {
      const auto due = due_time(item_time(*pending_));
      if (!wake_.wait_until(lock, std::min(due, std::chrono::steady_clock::now() + timeout),
                            [this] { return stopped_; }) &&
          std::chrono::steady_clock::now() < due) {
        return std::nullopt;
      }
      if (stopped_) return std::nullopt;
    }
    auto item = std::move(pending_);
    load_next();
    return item;
  }

  [[nodiscard]] bool finished() const override {
    std::lock_guard lock(mutex_);
    return stopped_ || !pending_;
  }

  void stop() override {
    {
      std::lock_guard lock(mutex_);
      stopped_ = true;
    }
    wake_.notify_all();
  }

 private:
  static SystemTime item_time(const StreamItem& item) {
    return std::visit([](const auto& value) { return value.time; }, item);
  }

  // Recorded pace: the first item comes at once, each later one when replay_delay
  // of its receive-time gap to the first has passed since the first came out.
  std::chrono::steady_clock::time_point due_time(SystemTime time) {
    if (!first_time_) {
      first_time_ = time;
      started_ = std::chrono::steady_clock::now();
    }
    return started_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                          replay_delay(time - *first_time_, options_.speed));
  }

  void load_next() {
    pending_.reset();
    while (samples_.has_row() || events_.has_row()) {
      const bool take_sample = samples_.has_row() && (!events_.has_row() || samples_.seq() < events_.seq());
      if (take_sample) {
        if (!options_.device.empty() && row_device(samples_.row()) != options_.device) {
          samples_.advance();
          continue;
        }
        Sample sample;
        read_sample_into(samples_.row(), sample);
        samples_.advance();
        pending_ = std::move(sample);
      } else {
        pending_ = read_event(events_.row());
        events_.advance();
      }
      return;
    }
    report_read_error();
  }

  // A capture damaged after it was opened ends the replay with one event saying why.
  void report_read_error() {
    const int code = samples_.failed_code() != 0 ? samples_.failed_code() : events_.failed_code();
    if (code == 0 || reported_error_) return;
    reported_error_ = true;
    pending_ = read_error_event(path_, database_.get(), code);
  }

  std::string path_;
  Database database_;
  Cursor samples_;
  Cursor events_;
  ReplayOptions options_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::optional<StreamItem> pending_;
  std::optional<SystemTime> first_time_;
  std::chrono::steady_clock::time_point started_;
  bool stopped_ = false;
  bool reported_error_ = false;
};

}  // namespace

std::chrono::nanoseconds replay_delay(std::chrono::nanoseconds recorded_gap, double speed) {
  if (speed <= 0 || recorded_gap.count() <= 0) return std::chrono::nanoseconds(0);
  return std::chrono::nanoseconds(static_cast<std::int64_t>(static_cast<double>(recorded_gap.count()) / speed));
}

Result<SampleSourcePtr> open_replay(const std::string& path, const ReplayOptions& options) {
  auto cursors = open_cursors(path);
  if (!cursors) return std::move(cursors).error();
  return SampleSourcePtr(std::make_unique<ReplaySource>(path, std::move(*cursors), options));
}

Result<std::size_t> capture_sample_bound(const std::string& path) {
  auto database = open_database(path, false, false, IntegrityCheck::by_caller);
  if (!database) return std::move(database).error();
  // Two subqueries: SQLite finds a lone min() or max() of the key at one end of the tree.
  auto span = prepare(path, database->get(),
                      "SELECT coalesce((SELECT max(seq) FROM samples) - (SELECT min(seq) FROM samples) + 1, 0)");
  if (!span) return make_error(Errc::io, "capture " + path + ": no samples table, not a rangekit capture");
  const int code = sqlite3_step(span->get());
  if (code != SQLITE_ROW) return sqlite_error(path, database->get(), code, "reading the samples' span");
  return static_cast<std::size_t>(std::max<std::int64_t>(sqlite3_column_int64(span->get(), 0), 0));
}

namespace {

// The array path with the samples read from the table's pages (capture_pages.hpp), the
// events through SQLite as before, merged by seq as the SQLite path merges them. One read
// transaction covers the schema check, the events and the pages, so a writer's checkpoint
// cannot change the file under the reader. False: the file does not qualify, nothing
// was handed over. For `samples` the page walker's checks (each page of the tree once, page
// types, bounds, key order, every record decoded) take the place of PRAGMA quick_check,
// which would read every row through SQLite's row engine again (slower than the read
// itself); the other tables, small, are checked by SQLite beside the read.
Result<bool> for_each_sample_page(const std::string& path, std::string_view device,
                                  const std::function<void(const Sample&)>& on_sample,
                                  const std::function<void(StreamEvent&&)>& on_event) {
  auto cursors = open_cursors(path, IntegrityCheck::by_caller, CaptureFields::array);
  if (!cursors) return std::move(cursors).error();
  // Named references, not a structured binding: a lambda below captures `events`, which
  // clang 14 (clang-tidy's front end) refuses for a binding.
  auto& database = cursors->database;
  auto& events = cursors->events;
  if (auto begun = execute(path, database.get(), "BEGIN"); !begun) return std::move(begun).error();
  auto root = samples_pages_root(path, database.get());
  if (!root) return std::move(root).error();
  if (!*root) return false;
  auto integrity = std::async(std::launch::async, [&path]() -> Status {
    auto checker = open_database(path, false, false, IntegrityCheck::by_caller);
    if (!checker) return std::move(checker).error();
    for (const char* table : {"meta", "sessions", "events"}) {
      if (auto checked = check_integrity(path, checker->get(), table); !checked) return checked;
    }
    return ok_status();
  });
  events.advance();
  const auto events_up_to = [&](std::optional<std::int64_t> seq) {
    while (events.has_row() && (!seq || events.seq() <= *seq)) {
      on_event(read_event(events.row()));
      events.advance();
    }
  };
  auto read = read_samples_pages(path, **root, device, [&](std::int64_t seq, const Sample& sample) {
    events_up_to(seq);
    on_sample(sample);
  });
  auto checked = integrity.get();
  if (!read) return std::move(read).error();
  if (!checked) return std::move(checked).error();
  events_up_to(std::nullopt);
  if (events.failed_code() != 0) on_event(read_error_event(path, database.get(), events.failed_code()));
  return true;
}

}  // namespace

Status for_each_in_capture(const std::string& path, std::string_view device,
                           const std::function<void(const Sample&)>& on_sample,
                           const std::function<void(StreamEvent&&)>& on_event, CaptureFields fields) {
  if (fields == CaptureFields::array) {
    auto direct = for_each_sample_page(path, device, on_sample, on_event);
    if (!direct) return std::move(direct).error();
    if (*direct) return ok_status();
  }
  auto cursors = open_cursors(path, IntegrityCheck::by_caller, fields);
  if (!cursors) return std::move(cursors).error();
  // PRAGMA quick_check reads the whole file as the scan does: it runs at the same time on
  // a second read-only connection, and its verdict decides whether the scan counts.
  auto integrity = std::async(std::launch::async, [&path]() -> Status {
    auto checker = open_database(path, false, false, IntegrityCheck::by_caller);
    if (!checker) return std::move(checker).error();
    return check_integrity(path, checker->get());
  });
  auto& [database, samples, events] = *cursors;
  samples.advance();
  events.advance();
  Sample sample;  // one for every row: its strings keep their storage
  while (samples.has_row() || events.has_row()) {
    if (samples.has_row() && (!events.has_row() || samples.seq() < events.seq())) {
      if (device.empty() || row_device(samples.row()) == device) {
        read_sample_into(samples.row(), sample);
        on_sample(sample);
      }
      samples.advance();
    } else {
      on_event(read_event(events.row()));
      events.advance();
    }
  }
  if (auto checked = integrity.get(); !checked) return checked;
  const int code = samples.failed_code() != 0 ? samples.failed_code() : events.failed_code();
  if (code != 0) on_event(read_error_event(path, database.get(), code));
  return ok_status();
}

}  // namespace rangekit::record
