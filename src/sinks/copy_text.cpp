// Doubles as the shortest text that reads back the same; NaN and infinities in the spelling
// PostgreSQL's float8 input takes.
#include "sinks/copy_text.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <ctime>

#include "rangekit/record/format.hpp"

namespace rangekit::sinks {
namespace {

void append_copy_double(std::string& out, double value) {
  if (std::isnan(value)) {
    out += "NaN";
    return;
  }
  if (std::isinf(value)) {
    out += value > 0 ? "Infinity" : "-Infinity";
    return;
  }
  std::array<char, 32> buffer{};
  const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  if (error == std::errc{}) out.append(buffer.data(), end);
}

void append_digits(std::string& out, long long value, int width) {
  std::array<char, 24> buffer{};
  const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  for (auto length = end - buffer.data(); length < width; ++length) out += '0';
  out.append(buffer.data(), end);
}

// Where the next byte COPY's text format escapes is, from `from`; text.size() when none.
std::size_t next_copy_special(std::string_view text, std::size_t from) {
  const auto found = std::find_if(text.begin() + static_cast<std::ptrdiff_t>(from), text.end(),
                                  [](char c) { return c == '\\' || c == '\t' || c == '\n' || c == '\r'; });
  return static_cast<std::size_t>(found - text.begin());
}

}  // namespace

void append_copy_escaped(std::string& out, std::string_view text) {
  // Runs of plain bytes in one append: the escaped bytes are rare (a sample's JSON has none
  // unless a string in it holds a quote or a control character).
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t next = next_copy_special(text, at);
    out.append(text, at, next - at);
    if (next == text.size()) break;
    switch (text[next]) {
      case '\\':
        out += "\\\\";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\n':
        out += "\\n";
        break;
      default:
        out += "\\r";
    }
    at = next + 1;
  }
}

void append_copy_time(std::string& out, std::int64_t time_ns) {
  // Floor to the microsecond, also before 1970.
  std::int64_t micros = time_ns / 1000 - (time_ns % 1000 < 0 ? 1 : 0);
  std::int64_t seconds = micros / 1'000'000;
  micros %= 1'000'000;
  if (micros < 0) {
    micros += 1'000'000;
    --seconds;
  }
  const auto as_time_t = static_cast<std::time_t>(seconds);
  std::tm fields{};
  ::gmtime_r(&as_time_t, &fields);
  append_digits(out, fields.tm_year + 1900LL, 4);
  out += '-';
  append_digits(out, fields.tm_mon + 1, 2);
  out += '-';
  append_digits(out, fields.tm_mday, 2);
  out += ' ';
  append_digits(out, fields.tm_hour, 2);
  out += ':';
  append_digits(out, fields.tm_min, 2);
  out += ':';
  append_digits(out, fields.tm_sec, 2);
  out += '.';
  append_digits(out, micros, 6);
  out += "+00";
}

std::string encode_copy_row(const SinkReading& reading) {
  std::string out;
  out.reserve(256);
  append_copy_time(out, reading.time_ns);
  out += '\t';
  append_copy_escaped(out, reading.sensor);
  out += '\t';
  append_digits(out, static_cast<long long>(reading.seq), 1);
  out += '\t';
  append_copy_double(out, reading.value);
  out += '\t';
  if (reading.unit.empty()) {
    out += "\\N";
  } else {
    append_copy_escaped(out, reading.unit);
  }
  out += reading.suspect ? "\tt\t" : "\tf\t";
  if (reading.sample == nullptr) {
    out += "\\N";
  } else {
    // Straight into the row; escaped in a second pass only when the JSON holds a byte to escape.
    const std::size_t json = out.size();
    record::append_jsonl(out, *reading.sample);
    if (out.size() > json && out.back() == '\n') out.pop_back();
    if (next_copy_special(out, json) != out.size()) {
      const std::string text = out.substr(json);
      out.resize(json);
      append_copy_escaped(out, text);
    }
  }
  if (reading.count == 0) {
    out += "\t\\N\t\\N\t\\N\n";
    return out;
  }
  out += '\t';
  append_digits(out, static_cast<long long>(reading.count), 1);
  out += '\t';
  append_copy_double(out, reading.min);
  out += '\t';
  append_copy_double(out, reading.max);
  out += '\n';
  return out;
}

}  // namespace rangekit::sinks
