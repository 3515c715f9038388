// `rangekit serve` with a postgres [[sink]], killed outright (kill -9) while the database is
// down and its spool fills: started again on the same site file and state folder with the
// database up, it sends every spooled reading, none doubled, and each seq goes on.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <fstream>
#include <regex>

#include "hub/site_fixture.hpp"
#include "rangekit/record/spool.hpp"
#include "rangekit/sinks/sink.hpp"
#include "sinks/postgres_cluster.hpp"

namespace {

using Clock = std::chrono::steady_clock;

// Rows in a spool another process writes (read-only, WAL: no lock on the writer); -1 when unreadable.
long long spooled_rows(const std::string& path) {
  sqlite3* db = nullptr;
  long long rows = -1;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_busy_timeout(db, 1000);
    sqlite3_stmt* count = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT count(*) FROM spool", -1, &count, nullptr) == SQLITE_OK &&
        sqlite3_step(count) == SQLITE_ROW) {
      rows = sqlite3_column_int64(count, 0);
    }
    sqlite3_finalize(count);
  }
  sqlite3_close(db);
  return rows;
}

TEST(ServePostgres, AKilledServiceSendsItsSpoolAtTheNextStart) {
  sinks_test::PostgresCluster cluster;
  ASSERT_TRUE(cluster.ready()) << cluster.failure;
  ASSERT_TRUE(cluster.require_password()) << cluster.failure;
  hub_test::Site site;
  const auto path = site.temp.path / "site.toml";
  // The password beside the site file, named relative to it.
  std::ofstream(site.temp.path / "pg.password") << "secret\n";
  std::ofstream(path) << "[service]\nlisten = \"127.0.0.1:0\"\n"
                      << hub_test::site_text(site.temp.path) << "[[sink]]\nkind = \"postgres\"\nurl = \""
                      << cluster.url() << "\"\npassword_file = \"pg.password\"\n";
  rangekit::hub::SinkConfig config;
  config.kind = "postgres";
  config.url = cluster.url();
  const std::string spool = (site.temp.path / "spool" / rangekit::sinks::spool_file_name(config)).string();
  ASSERT_TRUE(cluster.stop());
  {
    ls5_driver_test::Child service({"serve", "--config", path.string(), "--duration", "120"});
    const auto deadline = Clock::now() + std::chrono::seconds(30);
    while (spooled_rows(spool) < 300 && Clock::now() < deadline) {
      ::poll(nullptr, 0, 100);  // between looks at the spool, not a synchronisation
    }
    ASSERT_GE(spooled_rows(spool), 300) << "the spool fills while the database is down";
    service.kill_hard();
  }
  // What the killed service left on disk.
  std::map<std::string, std::set<std::uint64_t>> spooled;
  std::size_t spooled_count = 0;
  {
    auto left = rangekit::record::Spool::open(spool, 1 << 30);
    ASSERT_TRUE(left.ok()) << left.error().message;
    auto rows = (*left)->oldest(1'000'000);
    ASSERT_TRUE(rows.ok());
    spooled_count = rows->size();
    for (const auto& row : *rows) spooled[row.sensor].insert(row.seq);
  }
  ASSERT_GE(spooled_count, 300u);
  ASSERT_TRUE(cluster.start());
  auto run = ls5_driver_test::run_cli(site.temp.path, {"serve", "--config", path.string(), "--duration", "5"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.out.find("secret"), std::string::npos) << run.out;
  std::smatch counts;
  ASSERT_TRUE(std::regex_search(run.out, counts, std::regex(": written ([0-9]+), spooled ([0-9]+), dropped 0")))
      << run.out;
  const auto found = cluster.sequences();
  std::string problem;
  const long long total = sinks_test::complete_total(found, problem);
  EXPECT_TRUE(problem.empty()) << problem;
  EXPECT_EQ(total, static_cast<long long>(std::stoull(counts[1]))) << "the table holds what the second run wrote";
  std::size_t arrived = 0;
  bool went_on = false;
  for (const auto& [sensor, seqs] : spooled) {
    const auto there = found.find(sensor);
    ASSERT_NE(there, found.end()) << sensor;
    for (const std::uint64_t seq : seqs) arrived += there->second.count(seq);
    went_on = went_on || *there->second.rbegin() > *seqs.rbegin();
  }
  EXPECT_EQ(arrived, spooled_count) << "every spooled reading, once";
  EXPECT_TRUE(went_on) << "the second run's readings follow the spooled ones";
  std::cout << "spooled by the killed run " << spooled_count << ", written by the next " << counts[1] << "\n";
}

}  // namespace
