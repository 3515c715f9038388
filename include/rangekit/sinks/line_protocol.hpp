// InfluxDB line protocol, as InfluxDB 1.x /write, 2.x /api/v2/write and VictoriaMetrics read
// it: one reading a line. Pure text: no I/O here.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "rangekit/sinks/sink_reading.hpp"

namespace rangekit::sinks {

// Measurement names: comma and space escaped with a backslash.
std::string escape_measurement(std::string_view text);
// Tag keys, tag values and field keys: comma, equals sign and space escaped with a backslash.
std::string escape_tag(std::string_view text);
// String field values, without their double quotes: double quote and backslash escaped.
std::string escape_field_string(std::string_view text);

// Appends the reading's line (docs/sinks.md), ending in '\n': measurement `rangekit`, tags
// family/sensor/unit, fields value/suspect/seq (and count/min/max of a window), its time in ns.
// A line break in a name cannot be written (the protocol has no escape for it): it becomes an
// escaped space.
void append_line(std::string& out, const SinkReading& reading);
std::string encode_line(const SinkReading& reading);

}  // namespace rangekit::sinks
