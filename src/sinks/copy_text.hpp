// PostgreSQL's COPY text format (docs: COPY, "Text Format"): one row a line, columns split by
// tabs, \N for NULL. Pure text: no I/O here.
#pragma once

#include <string>
#include <string_view>

#include "rangekit/sinks/sink_reading.hpp"

namespace rangekit::sinks {

// Appends `text` as one COPY text column: backslash, tab, newline and carriage return written
// as \\, \t, \n and \r, so no byte of the text ends the column or the row.
void append_copy_escaped(std::string& out, std::string_view text);

// Appends a time in ns since the epoch as a timestamptz input, to the microsecond:
// "2026-12-07 11:24:24.123456+00".
void append_copy_time(std::string& out, std::int64_t time_ns);

// The columns of the postgres sink's rows, in this order (docs/sinks.md).
inline constexpr std::string_view copy_columns = "time, sensor, seq, value, unit, suspect, sample, count, min, max";

// The reading's COPY text row, ending in '\n': its time (µs), sensor, seq, value, unit (\N when
// none), suspect (t/f), its sample's JSON line (\N when none), and of a window count, min and
// max (\N for a single reading).
std::string encode_copy_row(const SinkReading& reading);

}  // namespace rangekit::sinks
