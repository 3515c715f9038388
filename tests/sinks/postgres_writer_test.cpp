// The postgres kind's writer against a real PostgreSQL 15 (postgres_cluster.hpp): a batch sent
// again is not doubled, text comes back as written, a value PostgreSQL refuses for good is a
// refused batch, the database down is a failed write, a table made by hand is used as it is.
#include <gtest/gtest.h>

#include <fstream>

#include "rangekit/sinks/sink.hpp"
#include "sinks/copy_text.hpp"
#include "sinks/postgres_cluster.hpp"
#include "sinks/postgres_writer.hpp"

namespace {

using namespace rangekit;
using Kind = sinks::WriteOutcome::Kind;

sinks::SinkOptions options_for(const std::string& url) {
  sinks::SinkOptions options;
  options.config.kind = "postgres";
  options.config.url = url;
  options.timeout = std::chrono::milliseconds(3000);
  return options;
}

// Rows of `sensor` with seq first..last, one a millisecond.
std::vector<record::SpoolRow> rows_of(const std::string& sensor, std::uint64_t first, std::uint64_t last) {
  std::vector<record::SpoolRow> rows;
  for (std::uint64_t seq = first; seq <= last; ++seq) {
    sinks::SinkReading reading;
    reading.sensor = sensor;
    reading.unit = "mm";
    reading.value = 20.0 + static_cast<double>(seq) / 8;
    reading.seq = seq;
    reading.time_ns = 1'765'000'000'000'000'000 + static_cast<std::int64_t>(seq) * 1'000'000;
    record::SpoolRow row;
    row.id = static_cast<std::int64_t>(seq);
    row.sensor = sensor;
    row.seq = seq;
    row.time_ns = reading.time_ns;
    row.line = sinks::encode_copy_row(reading);
    rows.push_back(std::move(row));
  }
  return rows;
}

std::unique_ptr<sinks::Writer> writer_for(const sinks::SinkOptions& options) {
  auto writer = sinks::open_postgres_writer(options);
  EXPECT_TRUE(writer.ok()) << writer.error().message;
  return writer ? std::move(*writer) : nullptr;
}

TEST(PostgresWriter, ABatchSentAgainIsNotDoubled) {
  sinks_test::PostgresCluster cluster;
  ASSERT_TRUE(cluster.ready()) << cluster.failure;
  auto writer = writer_for(options_for(cluster.url()));
  ASSERT_NE(writer, nullptr);
  const auto first = writer->write(rows_of("belt", 1, 1000));
  ASSERT_EQ(first.kind, Kind::confirmed) << first.why;
  // A crash after COMMIT, before the spool forgot the rows: they come again, with new ones.
  const auto again = writer->write(rows_of("belt", 500, 1500));
  ASSERT_EQ(again.kind, Kind::confirmed) << again.why;
  // And the batches after it, which repeat nothing.
  const auto next = writer->write(rows_of("belt", 1501, 2000));
  ASSERT_EQ(next.kind, Kind::confirmed) << next.why;
  const auto last = writer->write(rows_of("belt", 2001, 2500));
  ASSERT_EQ(last.kind, Kind::confirmed) << last.why;
  std::string problem;
  EXPECT_EQ(sinks_test::complete_total(cluster.sequences(), problem), 2500) << problem;
  EXPECT_EQ(cluster.value("SELECT count(*) FROM readings"), "2500");
  EXPECT_EQ(cluster.value("SELECT value FROM readings WHERE seq = 8"), "21");
  // The session says who it is, to the server's views and logs.
  EXPECT_EQ(cluster.value("SELECT count(*) FROM pg_stat_activity WHERE application_name = 'rangekit'"), "1");
}

TEST(PostgresWriter, TextComesBackAsWritten) {
  sinks_test::PostgresCluster cluster;
  ASSERT_TRUE(cluster.ready()) << cluster.failure;
  auto writer = writer_for(options_for(cluster.url()));
  ASSERT_NE(writer, nullptr);
  rangekit::Sample sample;
  sample.time = std::chrono::system_clock::time_point(std::chrono::milliseconds(1'765'000'000'123));
  sample.suspect = true;
  sample.suspect_reason = "tab\there \\ \"quoted\"\nnext";
  sinks::SinkReading reading;
  reading.sensor = "odd\tname\\with\nbreaks\r";
  reading.unit = "\\N";
  reading.value = 1.5;
  reading.suspect = true;
  reading.seq = 1;
  reading.time_ns = 1'765'000'000'123'456'789;
  reading.count = 3;
  reading.min = 1;
  reading.max = 2;
  reading.sample = &sample;
  record::SpoolRow row;
  row.line = sinks::encode_copy_row(reading);
  const auto written = writer->write({row});
  ASSERT_EQ(written.kind, Kind::confirmed) << written.why;
  const auto rows = cluster.query(
      "SELECT sensor, unit, suspect, count, min, max, sample->>'suspect_reason', "
      "to_char(time AT TIME ZONE 'UTC', 'YYYY-MM-DD HH24:MI:SS.US') FROM readings");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0][0], "odd\tname\\with\nbreaks\r");
  EXPECT_EQ(rows[0][1], "\\N") << "the text \\N, not NULL";
  EXPECT_EQ(cluster.value("SELECT unit IS NULL FROM readings"), "f");
  EXPECT_EQ(rows[0][2], "t");
  EXPECT_EQ(rows[0][3], "3");
  EXPECT_EQ(rows[0][4], "1");
  EXPECT_EQ(rows[0][5], "2");
  EXPECT_EQ(rows[0][6], "tab\there \\ \"quoted\"\nnext");
  EXPECT_EQ(rows[0][7], "2025-12-06 05:46:40.123456");
}

TEST(PostgresWriter, AValueNeverTakenIsRefusedAndTheNextBatchGoesIn) {
  sinks_test::PostgresCluster cluster;
  ASSERT_TRUE(cluster.ready()) << cluster.failure;
  auto writer = writer_for(options_for(cluster.url()));
  ASSERT_NE(writer, nullptr);
  auto rows = rows_of("belt", 1, 3);
  rows[1].line = "2025-12-06 05:46:40+00\tbelt\t2\tnot-a-number\tmm\tf\t\\N\t\\N\t\\N\t\\N\n";
  const auto refused = writer->write(rows);
  EXPECT_EQ(refused.kind, Kind::refused) << refused.why;
  EXPECT_NE(refused.why.find("invalid input syntax for type double precision"), std::string::npos) << refused.why;
  EXPECT_EQ(cluster.value("SELECT count(*) FROM readings"), "0") << "the batch is one transaction";
  const auto next = writer->write(rows_of("belt", 4, 6));
  EXPECT_EQ(next.kind, Kind::confirmed) << next.why;
  EXPECT_EQ(cluster.value("SELECT count(*) FROM readings"), "3");
}

TEST(PostgresWriter, TheDatabaseDownIsAFailedWriteAndUpAgainItConnectsAnew) {
  sinks_test::PostgresCluster cluster;
  ASSERT_TRUE(cluster.ready()) << cluster.failure;
  auto writer = writer_for(options_for(cluster.url()));
  ASSERT_NE(writer, nullptr);
  ASSERT_EQ(writer->write(rows_of("belt", 1, 10)).kind, Kind::confirmed);
  ASSERT_TRUE(cluster.stop());
  const auto down = writer->write(rows_of("belt", 11, 20));
  EXPECT_EQ(down.kind, Kind::failed);
  EXPECT_FALSE(down.why.empty());
  std::cout << "down: " << down.why << "\n";
  const auto still_down = writer->write(rows_of("belt", 11, 20));
  EXPECT_EQ(still_down.kind, Kind::failed);
  EXPECT_NE(still_down.why.find("Connection refused"), std::string::npos) << still_down.why;
  ASSERT_TRUE(cluster.start());
  const auto up = writer->write(rows_of("belt", 11, 20));
  EXPECT_EQ(up.kind, Kind::confirmed) << up.why;
  EXPECT_EQ(cluster.value("SELECT count(*) FROM readings"), "20");
}

TEST(PostgresWriter, ATableMadeByHandIsUsedAsItIs) {
  sinks_test::PostgresCluster cluster;
  ASSERT_TRUE(cluster.ready()) << cluster.failure;
  // Another column order, an id and a note of the plant's own, and another key name.
  ASSERT_TRUE(cluster.admin("plant",
                            "CREATE TABLE line_3 (id bigserial, note text DEFAULT 'by hand', sensor text NOT NULL, "
                            "seq bigint NOT NULL, time timestamptz NOT NULL, value double precision, unit text, "
                            "suspect boolean, sample jsonb, count integer, min double precision, "
                            "max double precision, CONSTRAINT line_3_key UNIQUE (sensor, seq)); "
                            "ALTER TABLE line_3 OWNER TO rangekit"))
      << cluster.failure;
  auto options = options_for(cluster.url());
  options.config.table = "line_3";
  auto writer = writer_for(options);
  ASSERT_NE(writer, nullptr);
  ASSERT_EQ(writer->write(rows_of("belt", 1, 50)).kind, Kind::confirmed);
  ASSERT_EQ(writer->write(rows_of("belt", 40, 60)).kind, Kind::confirmed);
  EXPECT_EQ(cluster.value("SELECT count(*) FROM line_3 WHERE note = 'by hand'"), "60");
  EXPECT_EQ(cluster.value("SELECT count(*) FROM line_3"), "60") << "the repeats were skipped";
  EXPECT_EQ(cluster.value("SELECT count(*) FROM information_schema.columns WHERE table_name = 'line_3'"), "12");
  EXPECT_EQ(cluster.value("SELECT count(*) FROM pg_tables WHERE schemaname = 'public'"), "1") << "no table of ours";
}

TEST(PostgresWriter, RefusesSettingsThatCannotWorkAtTheStart) {
  auto options = options_for("postgresql://rangekit@127.0.0.1:5432/plant?nonsense=1");
  auto bad_url = sinks::open_postgres_writer(options);
  ASSERT_FALSE(bad_url.ok());
  EXPECT_NE(bad_url.error().message.find("nonsense"), std::string::npos) << bad_url.error().message;
  options = options_for("postgresql://rangekit@127.0.0.1:5432/plant");
  options.config.password_file = "/nonexistent/rangekit-password";
  auto no_file = sinks::open_postgres_writer(options);
  ASSERT_FALSE(no_file.ok());
  EXPECT_EQ(no_file.error().message, "password_file /nonexistent/rangekit-password: cannot be read");
  options.config.password_file.clear();
  options.config.password_env = "RANGEKIT_TEST_NO_SUCH_VARIABLE";
  auto no_env = sinks::open_postgres_writer(options);
  ASSERT_FALSE(no_env.ok());
  EXPECT_EQ(no_env.error().message, "password_env: RANGEKIT_TEST_NO_SUCH_VARIABLE is not set");
  options.config.password_env.clear();
  options.config.table = "1readings";
  EXPECT_FALSE(sinks::open_postgres_writer(options).ok());
}

// The password is neither in the spool's name nor in what the sink says of itself.
TEST(PostgresWriter, APasswordInTheUrlStaysOutOfTheSpoolName) {
  hub::SinkConfig config;
  config.kind = "postgres";
  config.url = "postgresql://rangekit:hunter2@db.plant:5433/plant";
  EXPECT_EQ(sinks::spool_file_name(config), "postgres-rangekit-db.plant-5433-plant.spool");
  config.url = "postgresql://rangekit@db.plant:5433/plant";
  config.table = "line_3";
  EXPECT_EQ(sinks::spool_file_name(config), "postgres-rangekit-db.plant-5433-plant-line_3.spool");
}

}  // namespace
