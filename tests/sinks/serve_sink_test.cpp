// `rangekit serve` with a [[sink]]: --check describes it, and a run of the site's emulators
// into a real VictoriaMetrics says the sink at start and its counts at the end, and what it
// counts as written is in VictoriaMetrics.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "hub/site_fixture.hpp"
#include "sinks/victoria_metrics.hpp"

namespace {

TEST(ServeSink, StartsOnePerSinkTableAndSaysItsCounts) {
  sinks_test::VictoriaMetrics vm;
  ASSERT_GT(vm.pid, 0);
  hub_test::Site site;
  const auto path = site.temp.path / "site.toml";
  std::ofstream(path) << "[service]\nlisten = \"127.0.0.1:0\"\n"
                      << hub_test::site_text(site.temp.path) << "[[sink]]\nkind = \"influx\"\nurl = \""
                      << vm.write_url() << "\"\nsensors = [\"belt\", \"silo\"]\n";
  auto check = ls5_driver_test::run_cli(site.temp.path, {"serve", "--check", path.string()});
  EXPECT_EQ(check.exit_code, 0) << check.err;
  EXPECT_NE(check.out.find("sink " + vm.write_url() + " (influx): belt, silo, every reading"), std::string::npos)
      << check.out;

  auto run = ls5_driver_test::run_cli(site.temp.path, {"serve", "--config", path.string(), "--duration", "4"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("rangekit serve: sink " + vm.write_url() + " (influx): 2 sensors, spool " +
                         (site.temp.path / "spool").string()),
            std::string::npos)
      << run.out;
  std::smatch counts;
  const std::regex summary("sink " + vm.write_url() + ": written ([0-9]+), spooled ([0-9]+), dropped 0");
  ASSERT_TRUE(std::regex_search(run.out, counts, summary)) << run.out;
  const auto written = std::stoull(counts[1]);
  EXPECT_GT(written, 0u);
  // Only the sensors named, each sequence complete, as many as the sink says it wrote.
  std::string problem;
  EXPECT_EQ(sinks_test::settled_total(vm, static_cast<long long>(written), problem), static_cast<long long>(written))
      << problem;
  for (const auto& [sensor, values] : vm.sequences()) EXPECT_TRUE(sensor == "belt" || sensor == "silo") << sensor;
}

}  // namespace
