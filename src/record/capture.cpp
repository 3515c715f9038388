#include "rangekit/record/capture.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <charconv>
#include <cmath>
#include <set>
#include <string_view>
#include <utility>
#include <vector>

#include "capture_columns.hpp"
#include "rangekit/core/family.hpp"
#include "rangekit/record/format.hpp"
#include "rangekit/version.hpp"
#include "sqlite_handle.hpp"

namespace rangekit::record {
namespace {

// The project version from CMake (project(... VERSION)), recorded per session.
constexpr const char* rangekit_version = rangekit::version_string;

// The samples table comes from capture_columns.hpp, which the direct page reader compares.
std::string schema_sql() {
  return R"sql(
BEGIN;
CREATE TABLE IF NOT EXISTS meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);
INSERT OR IGNORE INTO meta(key, value) VALUES ('format', 'rangekit-capture'), ('format_version', '4');
CREATE TABLE IF NOT EXISTS sessions(
  id INTEGER PRIMARY KEY,
  started TEXT NOT NULL,
  started_ns INTEGER NOT NULL,
  ended_ns INTEGER,
  rangekit_version TEXT NOT NULL,
  sources TEXT NOT NULL DEFAULT '');
)sql" + std::string("CREATE TABLE IF NOT EXISTS ") +
         capture_layout().table_definition + R"sql(;
CREATE TABLE IF NOT EXISTS events(
  seq INTEGER PRIMARY KEY,
  session INTEGER NOT NULL,
  time_ns INTEGER NOT NULL,
  kind TEXT NOT NULL,
  message TEXT NOT NULL,
  count INTEGER NOT NULL);
COMMIT;
)sql";
}

// Every column of the layout, in its order: ?1 is seq.
std::string insert_sample_sql() {
  const CaptureLayout& layout = capture_layout();
  std::string names = "seq, session, time_ns, device, source, address, kind";
  for (const ChannelColumn& column : layout.channels) names += ", " + std::string(column.name);
  names += ", suspect, suspect_reason";
  std::string values;
  for (std::size_t index = 1; index <= layout.column_count(); ++index) {
    values += (index == 1 ? "?" : ", ?") + std::to_string(index);
  }
  return "INSERT INTO samples(" + names + ") VALUES (" + values + ")";
}
constexpr const char* insert_event_sql =
    "INSERT INTO events(seq, session, time_ns, kind, message, count) VALUES (?1, ?2, ?3, ?4, ?5, ?6)";

std::int64_t to_nanos(std::chrono::system_clock::time_point time) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(time.time_since_epoch()).count();
}

void bind_text(sqlite3_stmt* statement, int index, const std::string& text) {
  sqlite3_bind_text(statement, index, text.data(), static_cast<int>(text.size()), SQLITE_TRANSIENT);
}

// Text that outlives the statement's next step (write() binds every parameter afresh
// before each step), so SQLite need not copy it.
void bind_text_in_place(sqlite3_stmt* statement, int index, const std::string& text) {
  sqlite3_bind_text(statement, index, text.data(), static_cast<int>(text.size()), SQLITE_STATIC);
}

template <class T>
void bind_optional_integer(sqlite3_stmt* statement, int index, const std::optional<T>& value) {
  if (value) {
    sqlite3_bind_int64(statement, index, static_cast<std::int64_t>(*value));
  } else {
    sqlite3_bind_null(statement, index);
  }
}

// Targets as JSON text, exactly as nlohmann::json's dump() of
// [{"distance_m": d, "strength": s}, ...] writes it (keys in order, no spaces, doubles
// by nlohmann's own shortest round-trip printer, NaN and infinities as null), but
// straight into a reused buffer: building the json objects was most of a binning
// sample's capture cost.
void append_targets_json(std::string& out, const TargetList& targets) {
  out += '[';
  std::array<char, 64> number{};  // nlohmann's own number buffer size
  for (std::size_t i = 0; i < targets.size(); ++i) {
    out += i == 0 ? "{\"distance_m\":" : ",{\"distance_m\":";
    const double distance = targets[i].distance_m;
    if (std::isfinite(distance)) {
      const char* end = nlohmann::detail::to_chars(number.data(), number.data() + number.size(), distance);
      out.append(number.data(), static_cast<std::size_t>(end - number.data()));
    } else {
      out += "null";
    }
    out += ",\"strength\":";
    const auto printed = std::to_chars(number.data(), number.data() + number.size(), targets[i].strength);
    out.append(number.data(), printed.ptr);
    out += '}';
  }
  out += ']';
}

class SqliteCapture final : public CaptureSink {
 public:
  SqliteCapture(std::string path, Database database, CaptureOptions options)
      : path_(std::move(path)), database_(std::move(database)), options_(options) {}

  ~SqliteCapture() override { (void)close(); }

  Status start() {
    auto* db = database_.get();
    if (auto status = execute(path_, db, "PRAGMA journal_mode=WAL"); !status) return status;
    if (auto status = execute(path_, db, "PRAGMA synchronous=NORMAL"); !status) return status;
    if (options_.max_page_count > 0) {
      const auto pragma = "PRAGMA max_page_count=" + std::to_string(options_.max_page_count);
      if (auto status = execute(path_, db, pragma.c_str()); !status) return status;
    }
    if (auto status = execute(path_, db, schema_sql().c_str()); !status) {
      (void)execute(path_, db, "ROLLBACK");
      return status;
    }
    if (auto status = add_newer_columns(); !status) return status;
    if (auto status = read_next_seq(); !status) return status;
    if (auto status = insert_session(); !status) return status;
    auto samples = prepare(path_, db, insert_sample_sql().c_str());
    if (!samples) return std::move(samples).error();
    insert_sample_ = std::move(*samples);
    auto events = prepare(path_, db, insert_event_sql);
    if (!events) return std::move(events).error();
    insert_event_ = std::move(*events);
    return ok_status();
  }

  Status write(const Sample& sample) override {
    if (auto status = begin_batch(); !status) return status;
    auto* statement = insert_sample_.get();
    sqlite3_reset(statement);
    sqlite3_bind_int64(statement, 1, next_seq_);
    sqlite3_bind_int64(statement, 2, session_);
    sqlite3_bind_int64(statement, 3, to_nanos(sample.time));
    bind_text_in_place(statement, 4, sample.device);
    bind_text_in_place(statement, 5, sample.source.str());
    bind_optional_integer(statement, 6, sample.address >= 0 ? std::optional<int>(sample.address) : std::nullopt);
    const CaptureLayout& layout = capture_layout();
    if (columns_ == nullptr || columns_->family->name != sample.device) columns_ = layout.columns_of(sample.device);
    const KindDescriptor* kind = kind_of(columns_ != nullptr ? columns_->family : nullptr, sample);
    const std::string_view kind_name = kind_name_of(kind);
    sqlite3_bind_text(statement, 7, kind_name.data(), static_cast<int>(kind_name.size()), SQLITE_STATIC);
    bind_channels(statement, sample, kind);
    const int suspect = static_cast<int>(layout.suspect_column()) + 1;
    sqlite3_bind_int64(statement, suspect, sample.suspect ? 1 : 0);
    if (sample.suspect) {
      bind_text_in_place(statement, suspect + 1, sample.suspect_reason);
    } else {
      sqlite3_bind_null(statement, suspect + 1);
    }
    if (auto status = step(statement, "writing a sample"); !status) return status;
    ++batch_samples_;
    // Samples come from one source after another: only a change needs the set (and a string).
    if (!seen_source_ || sample.device != last_device_ || sample.source != last_source_) {
      seen_source_ = true;
      last_device_ = sample.device;
      last_source_ = sample.source;
      if (sources_.insert(sample.device + " " + sample.source.str()).second) sources_changed_ = true;
    }
    return commit_if_due();
  }

  Status write_event(const StreamEvent& event) override {
    if (auto status = begin_batch(); !status) return status;
    auto* statement = insert_event_.get();
    sqlite3_reset(statement);
    sqlite3_bind_int64(statement, 1, next_seq_);
    sqlite3_bind_int64(statement, 2, session_);
    sqlite3_bind_int64(statement, 3, to_nanos(event.time));
    sqlite3_bind_text(statement, 4, stream_event_kind_name(event.kind), -1, SQLITE_STATIC);
    bind_text(statement, 5, event.message);
    sqlite3_bind_int64(statement, 6, static_cast<std::int64_t>(event.count));
    if (auto status = step(statement, "writing an event"); !status) return status;
    return commit_if_due();
  }

  Status flush() override {
    if (failure_) return *failure_;
    if (!in_batch_) return ok_status();
    return commit();
  }

  [[nodiscard]] std::uint64_t committed_samples() const override { return committed_samples_; }
  [[nodiscard]] const std::string& path() const override { return path_; }

 private:
  // The channel columns: the values of the sample's family (columns_), NULL in the others.
  void bind_channels(sqlite3_stmt* statement, const Sample& sample, const KindDescriptor* kind) {
    const CaptureLayout& layout = capture_layout();
    const int first = static_cast<int>(CaptureLayout::first_channel_column) + 1;
    for (std::size_t column = 0; column < layout.channels.size(); ++column) {
      sqlite3_bind_null(statement, first + static_cast<int>(column));
    }
    if (columns_ == nullptr) return;
    const FamilyDescriptor& family = *columns_->family;
    for (std::size_t index = 0; index < family.channels.size(); ++index) {
      const auto column = columns_->column_of_channel[index];
      if (!column) continue;
      const int at = first + static_cast<int>(*column);
      const ChannelDescriptor& channel = family.channels[index];
      if (channel.form == ChannelForm::targets) {
        // A burst of no targets is kept as [] on a line of a kind that has them.
        const bool listed = kind != nullptr && kind->shows(index);
        if (!listed && sample.targets.empty()) continue;
        targets_text_.clear();
        append_targets_json(targets_text_, sample.targets);
        bind_text_in_place(statement, at, targets_text_);
        continue;
      }
      const auto value = sample.values.get(index);
      if (!value) continue;
      if (channel.form == ChannelForm::state) {
        const auto state = static_cast<std::size_t>(*value);
        if (*value >= 0 && state < channel.states.size()) {
          const std::string_view name = channel.states[state];
          sqlite3_bind_text(statement, at, name.data(), static_cast<int>(name.size()), SQLITE_STATIC);
        }
      } else if (layout.channels[*column].type == ColumnType::integer) {
        sqlite3_bind_int64(statement, at, std::llround(*value * channel.capture.scale));
      } else {
        sqlite3_bind_double(statement, at, *value);
      }
    }
  }

  Status close() {
    if (!database_) return ok_status();
    auto status = flush();
    if (status && !failure_) {
      const auto ended =
          "UPDATE sessions SET ended_ns = " + std::to_string(to_nanos(std::chrono::system_clock::now())) +
          " WHERE id = " + std::to_string(session_);
      (void)execute(path_, database_.get(), ended.c_str());
    }
    insert_sample_.reset();
    insert_event_.reset();
    database_.reset();
    return status;
  }

  // Each version added columns (the LS5 derivative and resolution, the quality flag, the
  // look-down overflow); an older capture gets them, NULL in its earlier rows, so that new
  // sessions can be appended to it.
  Status add_newer_columns() {
    const CaptureLayout& layout = capture_layout();
    std::vector<ChannelColumn> wanted = layout.channels;
    wanted.push_back({"suspect", ColumnType::integer});
    wanted.push_back({"suspect_reason", ColumnType::text});
    for (const auto& column : wanted) {
      const std::string name(column.name);
      auto present = has_column(path_, database_.get(), "samples", name.c_str());
      if (!present) return std::move(present).error();
      if (*present) continue;
      const std::string alter = "ALTER TABLE samples ADD COLUMN " + name + " " + sql_type(column.type);
      if (auto status = execute(path_, database_.get(), alter.c_str()); !status) return status;
    }
    return execute(path_, database_.get(), "UPDATE meta SET value = '4' WHERE key = 'format_version'");
  }

  Status read_next_seq() {
    auto query = prepare(path_, database_.get(),
                         "SELECT max(coalesce((SELECT max(seq) FROM samples), 0), "
                         "coalesce((SELECT max(seq) FROM events), 0))");
    if (!query) return std::move(query).error();
    const int code = sqlite3_step(query->get());
    if (code != SQLITE_ROW) return sqlite_error(path_, database_.get(), code, "reading the last sequence number");
    next_seq_ = sqlite3_column_int64(query->get(), 0) + 1;
    return ok_status();
  }

  Status insert_session() {
    auto insert = prepare(path_, database_.get(),
                          "INSERT INTO sessions(started, started_ns, rangekit_version) VALUES (?1, ?2, ?3)");
    if (!insert) return std::move(insert).error();
    const auto now = std::chrono::system_clock::now();
    std::string started;
    append_iso_time(started, now);
    bind_text(insert->get(), 1, started);
    sqlite3_bind_int64(insert->get(), 2, to_nanos(now));
    sqlite3_bind_text(insert->get(), 3, rangekit_version, -1, SQLITE_STATIC);
    if (auto status = step(insert->get(), "starting a session"); !status) return status;
    session_ = sqlite3_last_insert_rowid(database_.get());
    return ok_status();
  }

  Status step(sqlite3_stmt* statement, const char* what) {
    if (failure_) return *failure_;
    const int code = sqlite3_step(statement);
    sqlite3_reset(statement);
    if (code != SQLITE_DONE) return fail(sqlite_error(path_, database_.get(), code, what));
    ++next_seq_;
    return ok_status();
  }

  Status begin_batch() {
    if (failure_) return *failure_;
    if (in_batch_) return ok_status();
    if (auto status = execute(path_, database_.get(), "BEGIN"); !status) return fail(std::move(status).error());
    in_batch_ = true;
    batch_started_ = std::chrono::steady_clock::now();
    return ok_status();
  }

  Status commit_if_due() {
    ++batch_items_;
    if (batch_items_ >= options_.batch_samples ||
        std::chrono::steady_clock::now() - batch_started_ >= options_.batch_interval) {
      return commit();
    }
    return ok_status();
  }

  Status commit() {
    if (sources_changed_) {
      std::string list;
      for (const auto& source : sources_) list += (list.empty() ? "" : ", ") + source;
      auto update = prepare(path_, database_.get(), "UPDATE sessions SET sources = ?1 WHERE id = ?2");
      if (!update) return fail(std::move(update).error());
      bind_text(update->get(), 1, list);
      sqlite3_bind_int64(update->get(), 2, session_);
      const int code = sqlite3_step(update->get());
      if (code != SQLITE_DONE) return fail(sqlite_error(path_, database_.get(), code, "recording the sources"));
      sources_changed_ = false;
    }
    if (auto status = execute(path_, database_.get(), "COMMIT"); !status) return fail(std::move(status).error());
    in_batch_ = false;
    committed_samples_ += batch_samples_;
    batch_samples_ = 0;
    batch_items_ = 0;
    return ok_status();
  }

  // The open batch is lost; the file keeps every batch committed before.
  Status fail(Error error) {
    if (in_batch_ && sqlite3_get_autocommit(database_.get()) == 0) (void)execute(path_, database_.get(), "ROLLBACK");
    in_batch_ = false;
    failure_ = std::move(error);
    return *failure_;
  }

  std::string path_;
  Database database_;
  CaptureOptions options_;
  Statement insert_sample_;
  Statement insert_event_;
  std::int64_t session_ = 0;
  std::int64_t next_seq_ = 1;
  bool in_batch_ = false;
  std::chrono::steady_clock::time_point batch_started_;
  std::size_t batch_items_ = 0;
  std::uint64_t batch_samples_ = 0;
  std::uint64_t committed_samples_ = 0;
  std::set<std::string> sources_;
  bool seen_source_ = false;
  std::string last_device_;
  SharedName last_source_;
  bool sources_changed_ = false;
  std::string targets_text_;                // reused for every binning sample
  const FamilyColumns* columns_ = nullptr;  // of the last sample's family
  std::optional<Error> failure_;
};

}  // namespace

Result<std::unique_ptr<CaptureSink>> open_capture(const std::string& path, const CaptureOptions& options) {
  auto database = open_database(path, true, true);
  if (!database) return std::move(database).error();
  auto capture = std::make_unique<SqliteCapture>(path, std::move(*database), options);
  if (auto status = capture->start(); !status) return std::move(status).error();
  return std::unique_ptr<CaptureSink>(std::move(capture));
}

}  // namespace rangekit::record
