#include "capture_pages.hpp"

#include <sys/stat.h>

#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "capture_columns.hpp"
#include "sqlite_handle.hpp"
#include "sqlite_pages.hpp"
#include "sqlite_record.hpp"

namespace rangekit::record {
namespace {

using sqlite_pages::FieldValue;
using sqlite_pages::StorageClass;

// The places of the columns before the channels in a record of `samples` (capture_columns.hpp);
// seq is the rowid.
enum PageColumn : std::size_t { time_ns = 2, device = 3, address = 5, kind = 6 };

// A column's name by its place in the record, for a message.
std::string column_name(std::size_t column) {
  constexpr std::array<const char*, 7> fixed = {"seq", "session", "time_ns", "device", "source", "address", "kind"};
  const CaptureLayout& layout = capture_layout();
  if (column < fixed.size()) return fixed[column];
  if (column < layout.suspect_column()) return std::string(layout.channels[column - fixed.size()].name);
  return column == layout.suspect_column() ? "suspect" : "suspect_reason";
}

constexpr std::uint32_t utf8 = 1;

// A record's value that SQLite would convert where this reader does not (text in a number
// column, a number in a text column: only a file edited by hand holds one).
struct Mismatch {
  std::size_t column = 0;
  StorageClass type = StorageClass::null;
};

// The row's values as the SQLite reader's Column converts them (sqlite3_value_int64,
// sqlite3_value_double, sqlite3_value_text) for the storage classes the writer produces.
class Row {
 public:
  explicit Row(std::span<const FieldValue> fields) : fields_(fields) {}

  [[nodiscard]] bool is_null(std::size_t column) const { return fields_[column].type == StorageClass::null; }

  template <class T>
  [[nodiscard]] std::optional<T> integer(std::size_t column) {
    const FieldValue& field = fields_[column];
    if (field.type == StorageClass::integer) return static_cast<T>(field.integer);
    if (field.type == StorageClass::real) return static_cast<T>(real_to_integer(field.real));
    if (field.type != StorageClass::null) mismatch(column);
    return std::nullopt;
  }
  [[nodiscard]] std::optional<std::int64_t> integer(std::size_t column) { return integer<std::int64_t>(column); }
  [[nodiscard]] std::optional<double> real(std::size_t column) {
    const FieldValue& field = fields_[column];
    if (field.type == StorageClass::real) return field.real;
    // SQLite stores a REAL column's whole numbers as integers in the record.
    if (field.type == StorageClass::integer) return static_cast<double>(field.integer);
    if (field.type != StorageClass::null) mismatch(column);
    return std::nullopt;
  }
  // The text (empty when NULL).
  [[nodiscard]] std::string_view text(std::size_t column) {
    const FieldValue& field = fields_[column];
    if (field.type == StorageClass::text || field.type == StorageClass::blob) return field.bytes;
    if (field.type != StorageClass::null) mismatch(column);
    return {};
  }
  // The first value of a type the writer never stores in its column, or null.
  [[nodiscard]] const Mismatch* first_mismatch() const { return has_mismatch_ ? &mismatch_ : nullptr; }

 private:
  // sqlite3_value_int64 of a REAL: truncated, saturated at the int64 limits.
  static std::int64_t real_to_integer(double value) {
    constexpr auto lowest = std::numeric_limits<std::int64_t>::min();
    constexpr auto highest = std::numeric_limits<std::int64_t>::max();
    if (std::isnan(value)) return 0;
    if (value <= static_cast<double>(lowest)) return lowest;
    if (value >= static_cast<double>(highest)) return highest;
    return static_cast<std::int64_t>(value);
  }
  void mismatch(std::size_t column) {
    if (has_mismatch_) return;
    has_mismatch_ = true;
    mismatch_ = Mismatch{column, fields_[column].type};
  }

  std::span<const FieldValue> fields_;
  // A flag beside a value, not std::optional: g++ 12 at -O2 under TSan warned that the
  // optional's payload may be used uninitialized (-Werror), a false positive.
  bool has_mismatch_ = false;
  Mismatch mismatch_{};
};

const char* storage_name(StorageClass type) {
  switch (type) {
    case StorageClass::integer:
      return "an integer";
    case StorageClass::real:
      return "a real";
    case StorageClass::text:
      return "text";
    case StorageClass::blob:
      return "a blob";
    case StorageClass::null:
      break;
  }
  return "NULL";
}

// The fields of CaptureFields::array, as read_sample_into in replay.cpp fills them from
// the SQLite reader's row (source, the channels not shown in the stream and suspect_reason
// stay empty).
// The family and kind of the row before: rows of one source follow each other, so most rows
// are read without looking either up again.
struct LastLookup {
  const FamilyColumns* columns = nullptr;
  std::string kind_name;
  SampleKind kind{};
};

void fill_array_sample(Row& row, Sample& sample, LastLookup& last) {
  sample.time = std::chrono::system_clock::time_point(std::chrono::duration_cast<std::chrono::system_clock::duration>(
      std::chrono::nanoseconds(row.integer<std::int64_t>(time_ns).value_or(0))));
  const std::string_view family_name = row.text(device);
  if (sample.device != family_name) sample.device.assign(family_name);
  sample.address = row.integer<int>(address).value_or(-1);
  const CaptureLayout& layout = capture_layout();
  if (last.columns == nullptr || last.columns->family->name != family_name) {
    last.columns = layout.columns_of(family_name);
    last.kind_name.clear();
  }
  const FamilyColumns* columns = last.columns;
  sample.kind = SampleKind{};
  if (columns != nullptr) {
    const std::string_view kind_name = row.text(kind);
    if (kind_name != last.kind_name) {
      last.kind_name.assign(kind_name);
      last.kind = find_kind(*columns->family, kind_name).value_or(SampleKind{});
    }
    sample.kind = last.kind;
    read_channels(row, CaptureLayout::first_channel_column, *columns, sample, true);
  } else {
    sample.values.clear();
    sample.targets.clear();
  }
  sample.suspect = row.integer<int>(layout.suspect_column()).value_or(0) != 0;
  sample.suspect_reason.clear();
}

bool wal_is_empty(const std::string& path) {
  struct stat status {};
  const std::string wal = path + "-wal";
  return ::stat(wal.c_str(), &status) != 0 || status.st_size == 0;
}

}  // namespace

Result<std::optional<std::uint32_t>> samples_pages_root(const std::string& path, sqlite3* database) {
  auto query =
      prepare(path, database, "SELECT rootpage, sql FROM sqlite_schema WHERE type = 'table' AND name = 'samples'");
  if (!query) return std::move(query).error();
  const int code = sqlite3_step(query->get());
  if (code == SQLITE_DONE) return std::optional<std::uint32_t>();
  if (code != SQLITE_ROW) return sqlite_error(path, database, code, "reading the schema");
  const auto root = sqlite3_column_int64(query->get(), 0);
  const auto* sql = reinterpret_cast<const char*>(sqlite3_column_text(query->get(), 1));
  const std::string expected = "CREATE TABLE " + capture_layout().table_definition;
  // A capture of an older version, upgraded by ALTER TABLE, has another text (and the
  // same column places, but only this text is known for certain).
  if (sql == nullptr || expected != sql || root <= 1 || root > std::numeric_limits<std::uint32_t>::max()) {
    return std::optional<std::uint32_t>();
  }
  // The schema read above began the read transaction: from here on a checkpoint cannot
  // copy frames into the main file, so a log empty now stays empty for this reader.
  if (!wal_is_empty(path)) return std::optional<std::uint32_t>();
  auto encoding = prepare(path, database, "PRAGMA encoding");
  if (!encoding || sqlite3_step(encoding->get()) != SQLITE_ROW) return std::optional<std::uint32_t>();
  const auto* name = reinterpret_cast<const char*>(sqlite3_column_text(encoding->get(), 0));
  if (name == nullptr || std::string_view(name) != "UTF-8") return std::optional<std::uint32_t>();
  return std::optional<std::uint32_t>(static_cast<std::uint32_t>(root));
}

Status read_samples_pages(const std::string& path, std::uint32_t root, std::string_view wanted_device,
                          const std::function<void(std::int64_t seq, const Sample&)>& on_sample) {
  const std::string prefix = "capture " + path + ": corrupt samples table: ";
  auto pages = sqlite_pages::open_file_pages(path);
  if (!pages) return make_error(Errc::io, prefix + pages.error().message);
  if ((*pages)->geometry().text_encoding != utf8) return make_error(Errc::io, prefix + "text is not UTF-8");
  std::vector<FieldValue> fields(capture_layout().column_count());
  Sample sample;  // one for every row: its strings keep their storage
  LastLookup last;
  std::optional<Error> failure;
  auto walked = sqlite_pages::walk_table(**pages, root, [&](std::int64_t seq, std::span<const std::uint8_t> record) {
    if (!sqlite_pages::decode_record(record, fields)) {
      failure = make_error(Errc::io, prefix + "row " + std::to_string(seq) + ": malformed record");
      return false;
    }
    Row row(fields);
    if (!wanted_device.empty() && row.text(device) != wanted_device) return true;
    fill_array_sample(row, sample, last);
    if (const Mismatch* mismatch = row.first_mismatch()) {
      failure =
          make_error(Errc::io, prefix + "row " + std::to_string(seq) + ": column " + column_name(mismatch->column) +
                                   " holds " + storage_name(mismatch->type) + ", which rangekit never writes there");
      return false;
    }
    on_sample(seq, sample);
    return true;
  });
  if (failure) return *failure;
  if (!walked) return make_error(Errc::io, prefix + walked.error().message);
  return ok_status();
}

}  // namespace rangekit::record
