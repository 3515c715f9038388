// InfluxDB line protocol, as InfluxDB 1.x /write, 2.x /api/v2/write and VictoriaMetrics read
// it: one reading a line. Pure text: no I/O here.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace rangekit::sinks {

// What one line carries (docs/sinks.md): measurement `rangekit`, tags sensor/family/unit,
// fields value/suspect/seq, and the reading's time in ns since the Unix epoch.
struct LineReading {
  std::string_view sensor;
  std::string_view family;
  std::string_view unit;  // "m", "mm"; empty: no unit tag (line protocol has no empty tag value)
  double value = 0;
  bool suspect = false;
  std::uint64_t seq = 0;
  std::int64_t time_ns = 0;
};

// Measurement names: comma and space escaped with a backslash.
std::string escape_measurement(std::string_view text);
// Tag keys, tag values and field keys: comma, equals sign and space escaped with a backslash.
std::string escape_tag(std::string_view text);
// String field values, without their double quotes: double quote and backslash escaped.
std::string escape_field_string(std::string_view text);

// Appends the reading's line, ending in '\n'. A line break in a name cannot be written
// (the protocol has no escape for it): it becomes an escaped space.
void append_line(std::string& out, const LineReading& reading);
std::string encode_line(const LineReading& reading);

}  // namespace rangekit::sinks
