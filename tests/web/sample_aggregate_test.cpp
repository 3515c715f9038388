// `GET /api/events?max_rate=N` (docs/api.md): a sensor's samples merged per bucket.
#include "web/sample_aggregate.hpp"
#include "rangekit/ls5/family.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace {

using namespace rangekit;

Sample ls5(std::optional<double> distance_mm, bool suspect = false) {
  Sample sample;
  sample.device = "ls5";
  sample.kind = ls5::kind::result;
  sample.set(ls5::channel::distance_mm, distance_mm);
  sample.set(ls5::channel::signal, distance_mm ? ls5::SignalState::ok : ls5::SignalState::lost);
  sample.suspect = suspect;
  sample.set(ls5::channel::resolution_mm, 0.001);  // an LS5 of 25 mm range (table 3.1): 3 decimals
  return sample;
}

nlohmann::json data_of(const std::string& event) {
  const auto at = event.find("data: ");
  EXPECT_NE(at, std::string::npos) << event;
  return nlohmann::json::parse(event.substr(at + 6))["data"];
}

TEST(SampleAggregate, GapsAreCountedAndNeverPlotted) {
  web::SampleAggregate aggregate;
  aggregate.add(ls5(20.0), 1);
  aggregate.add(ls5(std::nullopt), 2);  // LS5 65535: "no signal" (§8)
  aggregate.add(ls5(10.0), 3);
  std::string out;
  aggregate.append_event(out, "belt");
  EXPECT_EQ(out.rfind("id: 3\nevent: aggregate\n", 0), 0U) << out;
  const auto data = data_of(out);
  EXPECT_EQ(data["count"], 3);
  EXPECT_EQ(data["gaps"], 1);
  EXPECT_EQ(data["suspect"], 0);
  EXPECT_DOUBLE_EQ(data["min"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(data["max"].get<double>(), 20.0);
  EXPECT_DOUBLE_EQ(data["last"].get<double>(), 10.0);
  EXPECT_EQ(data["unit"], "mm");
  EXPECT_TRUE(aggregate.empty());  // the event starts the next bucket
}

// A suspect sample stays marked; in a merged point it is counted and kept
// out of min/max/last, so one corrupt record cannot stretch the plotted window.
TEST(SampleAggregate, SuspectSamplesAreCountedAndKeptOutOfMinMaxLast) {
  web::SampleAggregate aggregate;
  aggregate.add(ls5(24.845), 7);
  aggregate.add(ls5(34.845, true), 8);
  std::string out;
  aggregate.append_event(out, "belt");
  const auto data = data_of(out);
  EXPECT_EQ(data["count"], 2);
  EXPECT_EQ(data["suspect"], 1);
  EXPECT_DOUBLE_EQ(data["max"].get<double>(), 24.845);
  EXPECT_DOUBLE_EQ(data["last"].get<double>(), 24.845);

  aggregate.add(ls5(34.845, true), 9);  // only suspect values: no figures at all
  out.clear();
  aggregate.append_event(out, "belt");
  EXPECT_FALSE(data_of(out).contains("min"));
}

}  // namespace
