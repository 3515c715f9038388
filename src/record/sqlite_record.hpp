// The record format of the SQLite file format: a header of serial types, then the
// values (https://www.sqlite.org/fileformat2.html#record_format). Values are views into
// the record's bytes; nothing is copied or allocated.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace rangekit::record::sqlite_pages {

enum class StorageClass : std::uint8_t { null, integer, real, text, blob };

struct FieldValue {
  StorageClass type = StorageClass::null;
  std::int64_t integer = 0;
  double real = 0;
  std::string_view bytes;  // text or blob
};

// Decodes the record's first fields.size() columns into `fields`; columns the record does
// not hold (added by ALTER TABLE after it was written) read as NULL. False when the record
// is malformed: its header or a value runs past its end, or a serial type is reserved.
[[nodiscard]] bool decode_record(std::span<const std::uint8_t> record, std::span<FieldValue> fields);

}  // namespace rangekit::record::sqlite_pages
