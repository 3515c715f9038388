// What `<base>/<sensor>/reading` carries: each sample under the rate, one window of their
// readings above it; no sample without a reading is ever counted as one.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "mqtt/reading_window.hpp"
#include "rangekit/core/family.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/uls/family.hpp"

namespace {

using namespace rangekit;
using namespace std::chrono_literals;
using Clock = mqtt::ReadingWindow::Clock;

Sample ls5_sample(std::optional<double> distance_mm, std::uint16_t code, ls5::SignalState signal) {
  Sample sample;
  sample.device = "ls5";
  sample.kind = ls5::kind::result;
  sample.set(ls5::channel::code, code);
  sample.set(ls5::channel::distance_mm, distance_mm);
  sample.set(ls5::channel::signal, signal);
  sample.set(ls5::channel::resolution_mm, 0.001);  // an LS5 of 25 mm range (table 3.1): 3 decimals
  return sample;
}

// L77: §8 "65534 – to indicate that the sensor has not made any measurements yet ...
// 65535 – to indicate that there is no signal." Neither is a distance.
TEST(ReadingWindow, L77NoSignalAndNoMeasurementYetAreCountedNeverADistance) {
  EXPECT_FALSE(reading_of(ls5_sample(std::nullopt, 65535, ls5::SignalState::lost)));
  EXPECT_FALSE(reading_of(ls5_sample(std::nullopt, 65534, ls5::SignalState::none_yet)));

  mqtt::ReadingWindow window(10);  // one message per 100 ms
  const auto start = Clock::now();
  ASSERT_TRUE(window.add(ls5_sample(20.0, 20000, ls5::SignalState::ok), start));  // the first goes out at once
  EXPECT_FALSE(window.add(ls5_sample(10.0, 10000, ls5::SignalState::ok), start + 10ms));
  EXPECT_FALSE(window.add(ls5_sample(std::nullopt, 65535, ls5::SignalState::lost), start + 20ms));
  EXPECT_FALSE(window.add(ls5_sample(30.0, 30000, ls5::SignalState::ok), start + 30ms));
  window.add_lost(2);
  EXPECT_FALSE(window.flush_due(start + 90ms));
  const auto text = window.flush_due(start + 100ms);
  ASSERT_TRUE(text);
  const auto json = nlohmann::json::parse(*text);
  EXPECT_EQ(json["window"], true);
  EXPECT_EQ(json["count"], 3);
  EXPECT_EQ(json["readings"], 2);
  EXPECT_EQ(json["channel"], "distance_mm");
  EXPECT_DOUBLE_EQ(json["min"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(json["mean"].get<double>(), 20.0);
  EXPECT_DOUBLE_EQ(json["max"].get<double>(), 30.0);
  EXPECT_DOUBLE_EQ(json["last"].get<double>(), 30.0);
  EXPECT_EQ(json["no_signal"], 1);
  EXPECT_EQ(json["lost"], 2);
  EXPECT_EQ(json["unit"], "mm");
  EXPECT_FALSE(window.flush_due(start + 300ms));  // nothing pending: nothing sent
}

// U107: §10 "Error Number ... Explanation" ($ER,n) is a measurement that failed: counted as an
// error, never a reading. A look-down edge reads as its presence, 1 or 0.
TEST(ReadingWindow, U107UlsErrorsAreCountedAndALookDownEdgeIsItsPresence) {
  Sample error;
  error.device = "uls";
  error.kind = uls::kind::error;
  error.set(uls::channel::error, 4);
  Sample binning;
  binning.device = "uls";
  binning.kind = uls::kind::binning;
  binning.targets = {{42.5, 10}, {12.25, 30}};
  Sample look_down;
  look_down.device = "uls";
  look_down.kind = uls::kind::look_down;
  look_down.set(uls::channel::presence, true);

  mqtt::ReadingWindow every(0);  // 0: every sample as `stream --format jsonl` writes it
  const auto own = every.add(error, Clock::now());
  ASSERT_TRUE(own);
  const auto json = nlohmann::json::parse(*own);
  EXPECT_EQ(json["error"], 4);
  EXPECT_FALSE(json.contains("distance_m"));

  mqtt::ReadingWindow window(1);
  const auto start = Clock::now();
  ASSERT_TRUE(window.add(binning, start));
  EXPECT_FALSE(window.add(error, start + 100ms));
  EXPECT_FALSE(window.add(look_down, start + 200ms));
  const auto text = window.flush_due(start + 1s);
  ASSERT_TRUE(text);
  const auto closed = nlohmann::json::parse(*text);
  EXPECT_EQ(closed["count"], 2);
  EXPECT_EQ(closed["errors"], 1);
  EXPECT_EQ(closed["readings"], 1);
  EXPECT_EQ(closed["channel"], "presence");
  EXPECT_EQ(closed["unit"], "");
  EXPECT_DOUBLE_EQ(closed["last"].get<double>(), 1.0);
  EXPECT_EQ(closed["presence"], true);
}

}  // namespace

// Suspect samples stay in captures and outputs, marked. A window is a
// summary, not the samples: a suspect distance is counted there and kept out of the figures,
// so one corrupt record (`34845` for `24845`) cannot move its min, mean, max or last.
TEST(ReadingWindow, SuspectSamplesAreCountedAndKeptOutOfTheFigures) {
  mqtt::ReadingWindow window(10);
  const auto start = Clock::now();
  ASSERT_TRUE(window.add(ls5_sample(24.845, 24845, ls5::SignalState::ok), start));
  auto corrupt = ls5_sample(34.845, 34845, ls5::SignalState::ok);
  corrupt.suspect = true;
  corrupt.suspect_reason = "jump";
  EXPECT_FALSE(window.add(ls5_sample(24.840, 24840, ls5::SignalState::ok), start + 10ms));
  EXPECT_FALSE(window.add(corrupt, start + 20ms));
  EXPECT_FALSE(window.add(ls5_sample(24.850, 24850, ls5::SignalState::ok), start + 30ms));
  const auto text = window.flush_due(start + 100ms);
  ASSERT_TRUE(text);
  const auto json = nlohmann::json::parse(*text);
  EXPECT_EQ(json["count"], 3);
  EXPECT_EQ(json["readings"], 2);
  EXPECT_EQ(json["suspect"], 1);
  EXPECT_DOUBLE_EQ(json["min"].get<double>(), 24.840);
  EXPECT_DOUBLE_EQ(json["max"].get<double>(), 24.850);
  EXPECT_DOUBLE_EQ(json["mean"].get<double>(), 24.845);
  EXPECT_DOUBLE_EQ(json["last"].get<double>(), 24.850);
}

// The figures carry the decimals the sensor's discreteness gives (as its samples print), not
// a binary fraction's tail: a mean of 15.7188 and 15.7187 mm with 0.0001 mm steps is 15.7188.
TEST(ReadingWindow, FiguresAreRoundedToTheSensorsDiscreteness) {
  mqtt::ReadingWindow window(10);
  const auto start = Clock::now();
  auto fine = [](double distance_mm) {
    auto sample = ls5_sample(distance_mm, 1, ls5::SignalState::ok);
    sample.set(ls5::channel::resolution_mm, 0.0001);
    return sample;
  };
  ASSERT_TRUE(window.add(fine(15.7), start));  // the first goes out alone
  EXPECT_FALSE(window.add(fine(15.718792959999998), start + 10ms));
  EXPECT_FALSE(window.add(fine(15.7187), start + 20ms));
  EXPECT_FALSE(window.add(fine(15.71879296), start + 30ms));
  const auto text = window.flush_due(start + 100ms);
  ASSERT_TRUE(text);
  EXPECT_NE(text->find("\"mean\":15.7188,"), std::string::npos) << *text;
  EXPECT_NE(text->find("\"last\":15.7188,"), std::string::npos) << *text;
  EXPECT_NE(text->find("\"min\":15.7187,"), std::string::npos) << *text;
}
