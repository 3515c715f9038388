// The `samples` table as this version of the capture writer creates it. SQLite keeps the
// text in sqlite_schema as "CREATE TABLE " + this; the direct page reader (capture_pages)
// reads a file's samples only when its schema is exactly this text, so that it knows
// each column's place in the record.
#pragma once

#include <string_view>

namespace rangekit::record {

inline constexpr std::string_view samples_table_definition = R"sql(samples(
  seq INTEGER PRIMARY KEY,
  session INTEGER NOT NULL,
  time_ns INTEGER NOT NULL,
  device TEXT NOT NULL,
  source TEXT NOT NULL,
  address INTEGER,
  kind TEXT NOT NULL,
  distance_m REAL,
  pulse_width INTEGER,
  targets TEXT,
  presence INTEGER,
  pulses_between_events INTEGER,
  device_error INTEGER,
  code INTEGER,
  distance_mm REAL,
  signal TEXT,
  derivative_mm REAL,
  resolution_mm REAL,
  suspect INTEGER,
  suspect_reason TEXT))sql";

}  // namespace rangekit::record
