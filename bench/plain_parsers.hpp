// Baselines for the decoder benchmarks: what a competent user would write with memchr and
// std::from_chars for the same work (frame, check, convert). They refuse a line without
// saying why; rangekit's decoders also name the problem, at no cost on good lines.
#pragma once

#include <charconv>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>

namespace rangekit::bench::plain {

// What a ULS measurement line holds; fields not sent stay 0.
struct UlsLine {
  bool addressed = false;
  std::uint8_t address = 0;
  double range_m = 0;  // in user units and metres
  double range_user = 0;
  std::uint32_t pulse_width_ps = 0;
  std::uint8_t index = 0;  // binning
  std::uint8_t count = 0;
  std::uint32_t strength = 0;
  int error_number = 0;  // $ER,n in the stream
};

enum class UlsShape { range, range_and_intensity, binning };

// An unsigned field of 1..max_digits digits, at most max_value.
inline bool read_unsigned(std::string_view field, std::size_t max_digits, std::uint32_t max_value, std::uint32_t& out) {
  if (field.empty() || field.size() > max_digits) return false;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), out);
  return error == std::errc{} && end == field.data() + field.size() && out <= max_value;
}

// §9, U9, U27: "[-]d.ddd" metres (3 decimals), at most 8 characters.
inline bool read_range_m(std::string_view field, double& out) {
  if (field.size() > 8 || field.size() < 5) return false;
  const std::size_t point = field.size() - 4;
  if (field[point] != '.') return false;
  const std::size_t first = field[0] == '-' ? 1 : 0;
  if (point == first) return false;
  for (std::size_t i = first; i < field.size(); ++i) {
    if (i != point && (field[i] < '0' || field[i] > '9')) return false;
  }
  return std::from_chars(field.data(), field.data() + field.size(), out).ec == std::errc{};
}

// One ULS line without its CR: start byte (and address), BM or ER, the fields of the shape.
inline bool parse_uls_line(std::string_view line, UlsShape shape, UlsLine& out) {
  if (line.size() < 2 || line.size() > 64) return false;
  for (std::size_t i = 1; i < line.size(); ++i) {  // §8: printable ASCII, no start byte inside
    const auto byte = static_cast<unsigned char>(line[i]);
    if (byte < 0x20 || byte >= 0x7F || byte == '$' || byte == '#') {
      if (!(i == 1 && line[0] == '#')) return false;
    }
  }
  std::size_t at = 1;
  out = UlsLine{};
  if (line[0] == '#') {
    const auto address = static_cast<unsigned char>(line[1]);
    if (address < 0x30 || address >= 0xF0) return false;  // U4: units 0x30-0xEF
    out.addressed = true;
    out.address = address;
    at = 2;
  } else if (line[0] != '$') {
    return false;
  }
  std::string_view body = line.substr(at);
  if (body.size() < 3 || body[2] != ',') return false;
  const char m0 = static_cast<char>(body[0] & ~0x20);  // U17: mnemonics in either case
  const char m1 = static_cast<char>(body[1] & ~0x20);
  body.remove_prefix(3);
  std::string_view fields[4];
  std::size_t count = 0;
  while (count < 4) {
    const std::size_t comma = body.find(',');
    fields[count++] = body.substr(0, comma);
    if (comma == std::string_view::npos) break;
    body.remove_prefix(comma + 1);
    if (count == 4) return false;  // more fields than any BM line has
  }
  std::uint32_t number = 0;
  if (m0 == 'E' && m1 == 'R') {  // U13: $ER,n in the stream
    if (count != 1 || !read_unsigned(fields[0], 3, 999, number) || number == 0) return false;
    out.error_number = static_cast<int>(number);
    return true;
  }
  if (m0 != 'B' || m1 != 'M') return false;
  switch (shape) {
    case UlsShape::range:
      if (count != 1 || !read_range_m(fields[0], out.range_user)) return false;
      break;
    case UlsShape::range_and_intensity:
      if (count != 2 || !read_range_m(fields[0], out.range_user) ||
          !read_unsigned(fields[1], 7, 9'999'999, out.pulse_width_ps)) {
        return false;
      }
      break;
    case UlsShape::binning: {
      std::uint32_t index = 0;
      if (count != 4 || !read_unsigned(fields[0], 2, 14, index) || !read_unsigned(fields[1], 2, 15, number) ||
          number == 0 || index >= number || !read_range_m(fields[2], out.range_user) ||
          !read_unsigned(fields[3], 5, 65535, out.strength)) {
        return false;
      }
      out.index = static_cast<std::uint8_t>(index);
      out.count = static_cast<std::uint8_t>(number);
      break;
    }
  }
  out.range_m = out.range_user;
  return true;
}

// The whole stream: frames split at CR with memchr; `use` gets every good line.
template <class Use>
std::size_t parse_uls_stream(std::string_view stream, UlsShape shape, Use&& use) {
  std::size_t good = 0;
  const char* at = stream.data();
  const char* const end = at + stream.size();
  UlsLine line;
  while (at < end) {
    const auto* cr = static_cast<const char*>(std::memchr(at, '\r', static_cast<std::size_t>(end - at)));
    if (cr == nullptr) break;
    if (parse_uls_line(std::string_view(at, static_cast<std::size_t>(cr - at)), shape, line)) {
      use(line);
      ++good;
    }
    at = cr + 1;
  }
  return good;
}

// LS5 stream record "!ddddd" (§9.2, L1): five digits, a result 0-50000 or 65534/65535 (§8.9, L7).
template <class Use>
std::size_t parse_ls5_stream(std::string_view stream, Use&& use) {
  std::size_t good = 0;
  const char* at = stream.data();
  const char* const end = at + stream.size();
  while (at < end) {
    const auto* cr = static_cast<const char*>(std::memchr(at, '\r', static_cast<std::size_t>(end - at)));
    if (cr == nullptr) break;
    std::uint32_t code = 0;
    if (cr - at == 6 && at[0] == '!') {
      bool digits = true;
      for (int i = 1; i < 6; ++i) digits = digits && at[i] >= '0' && at[i] <= '9';
      if (digits && std::from_chars(at + 1, cr, code).ec == std::errc{} &&
          (code <= 50000 || code == 65534 || code == 65535)) {
        use(static_cast<std::uint16_t>(code));
        ++good;
      }
    }
    at = cr + 1;
  }
  return good;
}

// LS5 UDP datagram (§10.1, L12): 512 bytes, XOR of bytes 0-509 in byte 511,
// 168 records of (code low, code high, state) with bit 1 set and bits 4-7 clear.
struct UdpRecord {
  std::uint16_t code = 0;
  std::uint8_t state = 0;
};
struct UdpDatagram {
  UdpRecord records[168];
  std::uint16_t serial = 0;
  std::uint16_t lower_boundary_mm = 0;
  std::uint16_t range_mm = 0;
  std::uint8_t counter = 0;
};

inline bool parse_udp_datagram(std::span<const std::uint8_t> bytes, UdpDatagram& out) {
  if (bytes.size() != 512) return false;
  std::uint8_t sum = 0;
  for (std::size_t i = 0; i < 510; ++i) sum = static_cast<std::uint8_t>(sum ^ bytes[i]);
  if (sum != bytes[511]) return false;
  for (std::size_t i = 0; i < 168; ++i) {
    const std::uint8_t state = bytes[3 * i + 2];
    if ((state & 0x02) == 0 || (state & 0xF0) != 0) return false;
    out.records[i] = {static_cast<std::uint16_t>(bytes[3 * i] | (bytes[3 * i + 1] << 8U)), state};
  }
  out.serial = static_cast<std::uint16_t>(bytes[504] | (bytes[505] << 8U));
  out.lower_boundary_mm = static_cast<std::uint16_t>(bytes[506] | (bytes[507] << 8U));
  out.range_mm = static_cast<std::uint16_t>(bytes[508] | (bytes[509] << 8U));
  out.counter = bytes[510];
  return true;
}

}  // namespace rangekit::bench::plain
