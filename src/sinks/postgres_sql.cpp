// Column types as docs/sinks.md lists them; time keeps microseconds (timestamptz's resolution).
#include "sinks/postgres_sql.hpp"

#include "sinks/copy_text.hpp"

namespace rangekit::sinks {
namespace {

constexpr std::string_view staging = "rangekit_incoming";

}  // namespace

std::string quote_identifier(std::string_view name) {
  std::string quoted = "\"";
  for (const char c : name) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + '"';
}

std::string create_table_sql(std::string_view table, bool hypertable) {
  return "CREATE TABLE IF NOT EXISTS " + quote_identifier(table) +
         " (time timestamptz NOT NULL, sensor text NOT NULL, seq bigint NOT NULL, value double precision, "
         "unit text, suspect boolean NOT NULL DEFAULT false, sample jsonb, count integer, min double precision, "
         "max double precision, PRIMARY KEY (sensor, seq" +
         std::string(hypertable ? ", time))" : "))");
}

std::string create_hypertable_sql(std::string_view table) {
  // A regclass literal: the quoted name inside single quotes (an identifier holds no quote).
  return "SELECT create_hypertable('" + quote_identifier(table) + "', 'time', if_not_exists => TRUE)";
}

std::string create_staging_sql() {
  return "CREATE TEMP TABLE IF NOT EXISTS " + std::string(staging) +
         " (time timestamptz, sensor text, seq bigint, value double precision, unit text, suspect boolean, "
         "sample jsonb, count integer, min double precision, max double precision) ON COMMIT DELETE ROWS";
}

std::string copy_into_table_sql(std::string_view table) {
  return "COPY " + quote_identifier(table) + " (" + std::string(copy_columns) + ") FROM STDIN";
}

std::string copy_into_staging_sql() {
  return "COPY " + std::string(staging) + " (" + std::string(copy_columns) + ") FROM STDIN";
}

std::string insert_from_staging_sql(std::string_view table) {
  // No conflict target: any unique key of the table absorbs the repeat, (sensor, seq) or a
  // hypertable's (sensor, seq, time).
  return "INSERT INTO " + quote_identifier(table) + " (" + std::string(copy_columns) + ") SELECT " +
         std::string(copy_columns) + " FROM " + std::string(staging) + " ON CONFLICT DO NOTHING";
}

}  // namespace rangekit::sinks
