// A sink on a live hub of emulators (hub/site_fixture.hpp) into a real VictoriaMetrics on
// loopback: every reading the sink says it wrote is there once, each sensor's sequence
// complete; and a historian stopped for a few seconds mid-run loses nothing.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <iostream>

#include "hub/site_fixture.hpp"
#include "poll_until.hpp"
#include "rangekit/hub/hub.hpp"
#include "rangekit/record/spool.hpp"
#include "rangekit/sinks/sink.hpp"
#include "sinks/victoria_metrics.hpp"

namespace {

using namespace rangekit;
using Clock = std::chrono::steady_clock;
using rangekit::test::poll_until;

sinks::SinkOptions options_for(const sinks_test::VictoriaMetrics& vm, const ls5_driver_test::TempDir& spool) {
  sinks::SinkOptions options;
  options.config.kind = "influx";
  options.config.url = vm.write_url();
  options.spool_dir = (spool.path / "spool").string();
  options.backoff_max = std::chrono::milliseconds(1000);
  return options;
}

// VictoriaMetrics holds exactly the sink's written readings, each sensor's sequence 1..N.
void expect_all_there_once(const sinks_test::VictoriaMetrics& vm, std::uint64_t written) {
  std::string problem;
  const long long total = sinks_test::settled_total(vm, static_cast<long long>(written), problem);
  EXPECT_TRUE(problem.empty()) << problem;
  EXPECT_EQ(total, static_cast<long long>(written));
  std::cout << "written " << written << ", in VictoriaMetrics " << total << "\n";
}

TEST(SinkVictoriaMetrics, EveryWrittenReadingArrivesOnce) {
  sinks_test::VictoriaMetrics vm;
  ASSERT_GT(vm.pid, 0);
  hub_test::Site site;
  auto hub = hub::Hub::start(site.config);
  ls5_driver_test::TempDir spool;
  auto sink = sinks::Sink::start(*hub, options_for(vm, spool));
  ASSERT_TRUE(sink.ok()) << sink.error().message;
  const auto started = Clock::now();
  // About 5 s of every sensor's readings, and some of each of the site's sensors in
  // VictoriaMetrics (under ThreadSanitizer and a loaded machine a bus unit can take longer).
  ASSERT_TRUE(poll_until(std::chrono::seconds(30),
                         [&] {
                           return Clock::now() - started >= std::chrono::seconds(5) &&
                                  (*sink)->stats().written >= 200 &&
                                  vm.sequences().size() == site.config.sensors.size();
                         }))
      << "written " << (*sink)->stats().written << ", sensors in VictoriaMetrics " << vm.sequences().size();
  (*sink)->stop();
  hub->stop();
  const sinks::SinkStats stats = (*sink)->stats();
  EXPECT_TRUE(stats.up);
  EXPECT_EQ(stats.dropped, 0u);
  EXPECT_EQ(stats.rejected, 0u);
  expect_all_there_once(vm, stats.written);
  EXPECT_EQ(vm.sequences().size(), site.config.sensors.size()) << "a sequence for each sensor of the site";
}

TEST(SinkVictoriaMetrics, AStoppedHistorianLosesNothing) {
  sinks_test::VictoriaMetrics vm;
  ASSERT_GT(vm.pid, 0);
  hub_test::Site site;
  auto hub = hub::Hub::start(site.config);
  ls5_driver_test::TempDir spool;
  auto sink = sinks::Sink::start(*hub, options_for(vm, spool));
  ASSERT_TRUE(sink.ok()) << sink.error().message;
  ASSERT_TRUE(poll_until(std::chrono::seconds(15), [&] { return (*sink)->stats().written >= 100; }));
  vm.stop();
  // Down, and readings pile up in the spool for a few seconds.
  const auto stopped = Clock::now();
  ASSERT_TRUE(poll_until(std::chrono::seconds(15), [&] {
    const auto stats = (*sink)->stats();
    return !stats.up && stats.failures >= 2 && Clock::now() - stopped >= std::chrono::seconds(3);
  }));
  const sinks::SinkStats during = (*sink)->stats();
  EXPECT_GT(during.spooled, 100u) << "readings wait in the spool";
  std::cout << "down: " << during.spooled << " rows spooled, oldest " << during.oldest_age_s << " s, "
            << during.failures << " failed writes (" << during.error << ")\n";
  EXPECT_GT(during.oldest_age_s, 1.0);
  ASSERT_TRUE(vm.start());
  // Back up, and the backlog drained: what waited at the restart went out.
  const std::uint64_t due = during.written + during.spooled;
  ASSERT_TRUE(poll_until(std::chrono::seconds(15),
                         [&] {
                           const auto stats = (*sink)->stats();
                           return stats.up && stats.written >= due;
                         }))
      << "written " << (*sink)->stats().written << " of " << due;
  (*sink)->stop();
  hub->stop();
  const sinks::SinkStats stats = (*sink)->stats();
  EXPECT_EQ(stats.dropped, 0u);
  EXPECT_EQ(stats.rejected, 0u);
  expect_all_there_once(vm, stats.written);
}

}  // namespace

namespace {

// A sink stopped while the historian is away keeps its rows on disk; the next one on the same
// spool sends them first, and each sensor's seq goes on where it was.
TEST(SinkVictoriaMetrics, TheNextStartSendsTheSpoolFirstAndSeqGoesOn) {
  sinks_test::VictoriaMetrics vm;
  ASSERT_GT(vm.pid, 0);
  vm.stop();
  hub_test::Site site;
  auto hub = hub::Hub::start(site.config);
  ls5_driver_test::TempDir spool;
  std::uint64_t waiting = 0;
  {
    auto sink = sinks::Sink::start(*hub, options_for(vm, spool));
    ASSERT_TRUE(sink.ok()) << sink.error().message;
    ASSERT_TRUE(poll_until(std::chrono::seconds(15), [&] {
      const auto stats = (*sink)->stats();
      return stats.failures >= 1 && stats.spooled >= 100;
    }));
    (*sink)->stop();
    waiting = (*sink)->stats().spooled;
    EXPECT_EQ((*sink)->stats().written, 0u);
  }
  ASSERT_TRUE(vm.start());
  auto sink = sinks::Sink::start(*hub, options_for(vm, spool));
  ASSERT_TRUE(sink.ok()) << sink.error().message;
  EXPECT_GE((*sink)->stats().spooled, waiting) << "the earlier run's rows are in the reopened spool";
  ASSERT_TRUE(poll_until(std::chrono::seconds(15), [&] { return (*sink)->stats().written >= waiting + 100; }));
  (*sink)->stop();
  hub->stop();
  std::cout << "spooled by the first run " << waiting << "\n";
  expect_all_there_once(vm, (*sink)->stats().written);
}

}  // namespace

namespace {

// A backlog drains at most drain_rate rows a second: 3000 spooled rows at 1000 rows/s take
// about 3 s, not the one write they would fit in.
TEST(SinkVictoriaMetrics, ABacklogDrainsAtDrainRate) {
  sinks_test::VictoriaMetrics vm;
  ASSERT_GT(vm.pid, 0);
  ls5_driver_test::TempDir spool;
  auto options = options_for(vm, spool);
  options.config.drain_rate = 1000;
  {
    std::filesystem::create_directories(options.spool_dir);
    auto backlog = record::Spool::open(
        (std::filesystem::path(options.spool_dir) / sinks::spool_file_name(options.config)).string(), 1 << 26);
    ASSERT_TRUE(backlog.ok()) << backlog.error().message;
    std::vector<record::SpoolRow> rows;
    const auto now =
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
            .count();
    for (std::int64_t i = 0; i < 3000; ++i) {
      record::SpoolRow row;
      row.sensor = "belt";
      row.seq = (*backlog)->next_seq("belt");
      row.time_ns = now - 10'000'000'000 + i * 1'000'000;
      row.line = "rangekit,family=ls5,sensor=belt,unit=mm value=20,suspect=false,seq=" + std::to_string(row.seq) +
                 "i " + std::to_string(row.time_ns) + "\n";
      rows.push_back(std::move(row));
    }
    ASSERT_TRUE((*backlog)->append(rows).ok());
  }
  hub::SiteConfig no_sensors;
  auto hub = hub::Hub::start(no_sensors);
  const auto started = Clock::now();
  auto sink = sinks::Sink::start(*hub, options);
  ASSERT_TRUE(sink.ok()) << sink.error().message;
  ASSERT_TRUE(poll_until(std::chrono::seconds(15), [&] { return (*sink)->stats().written >= 3000; }));
  const double took = std::chrono::duration<double>(Clock::now() - started).count();
  std::cout << "3000 rows at drain_rate 1000 took " << took << " s\n";
  EXPECT_GE(took, 2.5);
  EXPECT_LE(took, 6.0);
  (*sink)->stop();
  expect_all_there_once(vm, (*sink)->stats().written);
}

}  // namespace
