// The SQL the postgres sink sends: its table, COPY into it, and for a batch sent again after a
// crash the session's staging table and the move from it that skips rows the table has.
#pragma once

#include <string>
#include <string_view>

namespace rangekit::sinks {

// "readings" → "\"readings\"": quoted, so a name is taken as written (case, reserved words).
std::string quote_identifier(std::string_view name);
// CREATE TABLE IF NOT EXISTS with the sink's columns; the key is (sensor, seq), or
// (sensor, seq, time) for a TimescaleDB hypertable, whose unique keys must hold its time column.
std::string create_table_sql(std::string_view table, bool hypertable);
// SELECT create_hypertable(table, 'time', if_not_exists => TRUE).
std::string create_hypertable_sql(std::string_view table);
// COPY straight into the table: a batch never sent before.
std::string copy_into_table_sql(std::string_view table);
// The session's staging table: COPY lands here, emptied at each COMMIT.
std::string create_staging_sql();
std::string copy_into_staging_sql();
// Staging into the table; a row whose key the table has already is left out.
std::string insert_from_staging_sql(std::string_view table);

}  // namespace rangekit::sinks
