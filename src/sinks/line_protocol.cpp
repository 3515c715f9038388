// Escaping per the line-protocol reference's "special characters" rules; a value as the
// shortest text that reads back as the same double.
#include "rangekit/sinks/line_protocol.hpp"

#include <array>
#include <charconv>
#include <cmath>

namespace rangekit::sinks {
namespace {

std::string escaped(std::string_view text, std::string_view special) {
  std::string out;
  out.reserve(text.size() + 4);
  for (const char c : text) {
    if (c == '\n' || c == '\r') {
      out += "\\ ";
      continue;
    }
    if (special.find(c) != std::string_view::npos) out += '\\';
    out += c;
  }
  return out;
}

void append_double(std::string& out, double value) {
  if (!std::isfinite(value)) value = 0;  // the protocol has no NaN or infinity; a reading never is one
  std::array<char, 32> buffer{};
  // Shortest text that reads back as the same double.
  const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  if (error == std::errc{}) out.append(buffer.data(), end);
}

}  // namespace

std::string escape_measurement(std::string_view text) { return escaped(text, ", "); }
std::string escape_tag(std::string_view text) { return escaped(text, ",= "); }
std::string escape_field_string(std::string_view text) { return escaped(text, "\"\\"); }

void append_line(std::string& out, const SinkReading& reading) {
  out += "rangekit";
  // Tags in key order (family, sensor, unit): the order the reference asks for, for speed.
  if (!reading.family.empty()) out += ",family=" + escape_tag(reading.family);
  if (!reading.sensor.empty()) out += ",sensor=" + escape_tag(reading.sensor);
  if (!reading.unit.empty()) out += ",unit=" + escape_tag(reading.unit);
  out += " value=";
  append_double(out, reading.value);
  out += reading.suspect ? ",suspect=true" : ",suspect=false";
  out += ",seq=" + std::to_string(reading.seq) + "i";
  if (reading.count > 0) {
    out += ",count=" + std::to_string(reading.count) + "i,min=";
    append_double(out, reading.min);
    out += ",max=";
    append_double(out, reading.max);
  }
  out += ' ';
  out += std::to_string(reading.time_ns);
  out += '\n';
}

std::string encode_line(const SinkReading& reading) {
  std::string out;
  append_line(out, reading);
  return out;
}

}  // namespace rangekit::sinks
