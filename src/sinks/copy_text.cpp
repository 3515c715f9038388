// Doubles as the shortest text that reads back the same; NaN and infinities in the spelling
// PostgreSQL's float8 input takes.
#include "sinks/copy_text.hpp"

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

}  // namespace

void append_copy_escaped(std::string& out, std::string_view text) {
  for (const char c : text) {
    switch (c) {
      case '\\':
        out += "\\\\";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        out += c;
    }
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
    std::string json;
    record::append_jsonl(json, *reading.sample);
    if (!json.empty() && json.back() == '\n') json.pop_back();
    append_copy_escaped(out, json);
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
