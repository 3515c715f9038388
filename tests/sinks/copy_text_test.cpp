// The COPY text rows of the postgres sink, the expected text typed by hand from PostgreSQL's
// documentation (COPY, "Text Format"): columns split by a tab, rows ended by a newline, \N for
// NULL; backslash, newline, carriage return and the delimiter (tab) inside a value preceded by
// a backslash, written as \\, \n, \r and \t.
#include "sinks/copy_text.hpp"

#include <gtest/gtest.h>

#include "sinks/postgres_sql.hpp"

namespace {

using namespace rangekit::sinks;

std::string escaped(std::string_view text) {
  std::string out;
  append_copy_escaped(out, text);
  return out;
}

TEST(CopyText, EscapesPerTheTextFormat) {
  EXPECT_EQ(escaped("bay A"), "bay A");
  EXPECT_EQ(escaped("a\tb"), R"(a\tb)");
  EXPECT_EQ(escaped("two\nlines"), R"(two\nlines)");
  EXPECT_EQ(escaped("cr\rlf\n"), R"(cr\rlf\n)");
  EXPECT_EQ(escaped(R"(C:\data)"), R"(C:\\data)");
  // Text that reads "\N" is data, not NULL: its backslash is doubled.
  EXPECT_EQ(escaped(R"(\N)"), R"(\\N)");
  // Nothing else is special: quotes, commas, other control characters pass as they are.
  EXPECT_EQ(escaped("say \"hi\", 'x'\x01"), "say \"hi\", 'x'\x01");
}

TEST(CopyText, WritesTimesToTheMicrosecondInUtc) {
  std::string out;
  append_copy_time(out, 1700000000123456789);  // 2023-11-14T22:13:20.123456789Z
  EXPECT_EQ(out, "2023-11-14 22:13:20.123456+00");
  out.clear();
  append_copy_time(out, -1);  // floored, not rounded toward 1970
  EXPECT_EQ(out, "1969-12-31 23:59:59.999999+00");
  out.clear();
  append_copy_time(out, 0);
  EXPECT_EQ(out, "1970-01-01 00:00:00.000000+00");
}

TEST(CopyText, WritesASingleReadingWithNullWindowFigures) {
  SinkReading reading;
  reading.sensor = "bay\tA";
  reading.unit = "m";
  reading.value = 1.25;
  reading.suspect = true;
  reading.seq = 17;
  reading.time_ns = 1700000000123456789;
  EXPECT_EQ(encode_copy_row(reading), "2023-11-14 22:13:20.123456+00\tbay\\tA\t17\t1.25\tm\tt\t\\N\t\\N\t\\N\t\\N\n");
}

TEST(CopyText, WritesAWindowsFiguresAndNullForNoUnit) {
  SinkReading reading;
  reading.sensor = "belt";
  reading.value = 15.718792959999998;  // every digit kept
  reading.seq = 3;
  reading.time_ns = 5'000;
  reading.count = 40;
  reading.min = -0.5;
  reading.max = 1e300;
  EXPECT_EQ(encode_copy_row(reading),
            "1970-01-01 00:00:00.000005+00\tbelt\t3\t15.718792959999998\t\\N\tf\t\\N\t40\t-0.5\t1e+300\n");
}

TEST(CopyText, WritesTheSampleAsItsJsonLineEscaped) {
  rangekit::Sample sample;
  sample.suspect = true;
  sample.suspect_reason = "say \"hi\"";
  SinkReading reading;
  reading.sensor = "belt";
  reading.seq = 1;
  reading.sample = &sample;
  const std::string row = encode_copy_row(reading);
  // The JSON's own backslashes are doubled; the line's newline is not written.
  EXPECT_NE(row.find(R"("suspect_reason":"say \\"hi\\""})"), std::string::npos) << row;
  EXPECT_NE(row.find("\tf\t{\"time\":\""), std::string::npos) << row;
  EXPECT_EQ(std::count(row.begin(), row.end(), '\n'), 1);
  EXPECT_EQ(std::count(row.begin(), row.end(), '\t'), 9);
}

TEST(CopyText, WritesNaNAndInfinityAsFloat8ReadsThem) {
  SinkReading reading;
  reading.sensor = "s";
  reading.value = std::numeric_limits<double>::quiet_NaN();
  reading.count = 1;
  reading.min = -std::numeric_limits<double>::infinity();
  reading.max = std::numeric_limits<double>::infinity();
  EXPECT_EQ(encode_copy_row(reading),
            "1970-01-01 00:00:00.000000+00\ts\t0\tNaN\t\\N\tf\t\\N\t1\t-Infinity\tInfinity\n");
}

TEST(PostgresSql, QuotesTheTableAndSkipsKeysItHolds) {
  EXPECT_EQ(quote_identifier("readings"), "\"readings\"");
  EXPECT_EQ(quote_identifier("a\"b"), "\"a\"\"b\"");
  EXPECT_NE(create_table_sql("Plant_1", false).find("CREATE TABLE IF NOT EXISTS \"Plant_1\" ("), std::string::npos);
  EXPECT_NE(create_table_sql("t", false).find("PRIMARY KEY (sensor, seq))"), std::string::npos);
  EXPECT_NE(create_table_sql("t", true).find("PRIMARY KEY (sensor, seq, time))"), std::string::npos);
  EXPECT_EQ(create_hypertable_sql("t"), "SELECT create_hypertable('\"t\"', 'time', if_not_exists => TRUE)");
  EXPECT_EQ(copy_into_table_sql("t"),
            "COPY \"t\" (time, sensor, seq, value, unit, suspect, sample, count, min, max) FROM STDIN");
  EXPECT_EQ(insert_from_staging_sql("t"),
            "INSERT INTO \"t\" (time, sensor, seq, value, unit, suspect, sample, count, min, max) SELECT time, sensor, "
            "seq, value, unit, suspect, sample, count, min, max FROM rangekit_incoming ON CONFLICT DO NOTHING");
}

}  // namespace
