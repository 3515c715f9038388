#include "sqlite_record.hpp"
#include "sqlite_varint.hpp"

#include <bit>
#include <cstring>

namespace rangekit::record::sqlite_pages {
namespace {

// A big-endian two's complement integer of `count` bytes (1-8).
std::int64_t signed_big_endian(const std::uint8_t* bytes, std::size_t count) {
  std::uint64_t value = (bytes[0] & 0x80U) != 0 ? ~std::uint64_t{0} : 0;
  for (std::size_t i = 0; i < count; ++i) value = (value << 8U) | bytes[i];
  return static_cast<std::int64_t>(value);
}

// Bytes of the value of each integer serial type 1-6.
constexpr std::size_t integer_sizes[] = {0, 1, 2, 3, 4, 6, 8};

}  // namespace

bool decode_record(std::span<const std::uint8_t> record, std::span<FieldValue> fields) {
  const std::uint8_t* bytes = record.data();
  const std::size_t size = record.size();
  std::size_t offset = 0;
  std::uint64_t header_size = 0;
  if (!read_varint(bytes, size, offset, header_size) || header_size > size || header_size < offset) return false;
  const auto header_end = static_cast<std::size_t>(header_size);
  std::size_t body = header_end;
  for (FieldValue& field : fields) {
    field = FieldValue{};
    if (offset >= header_end) continue;  // a column added after the row was written
    std::uint64_t serial = 0;
    if (!read_varint(bytes, header_end, offset, serial)) return false;
    if (serial == 0) continue;
    if (serial <= 6) {
      const std::size_t width = integer_sizes[serial];
      if (body + width > size) return false;
      field.type = StorageClass::integer;
      field.integer = signed_big_endian(bytes + body, width);
      body += width;
    } else if (serial == 7) {
      if (body + 8 > size) return false;
      field.type = StorageClass::real;
      field.real = std::bit_cast<double>(static_cast<std::uint64_t>(signed_big_endian(bytes + body, 8)));
      body += 8;
    } else if (serial == 8 || serial == 9) {
      field.type = StorageClass::integer;
      field.integer = serial == 9 ? 1 : 0;
    } else if (serial >= 12) {
      const std::uint64_t length = (serial - 12) / 2;
      if (length > size - body) return false;
      field.type = (serial & 1U) != 0 ? StorageClass::text : StorageClass::blob;
      field.bytes = std::string_view(reinterpret_cast<const char*>(bytes + body), static_cast<std::size_t>(length));
      body += static_cast<std::size_t>(length);
    } else {
      return false;  // 10 and 11 are reserved
    }
  }
  return true;
}

}  // namespace rangekit::record::sqlite_pages
