// One reading per sample, the same in every face: the samples below go through a capture, an
// SSE aggregate, an MQTT window and Python, and each face must report the value, unit and
// channel its family defines (core/family.hpp), or a gap where there is none.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "build_paths.hpp"
#include "cli/cli_run.hpp"
#include "mqtt/reading_window.hpp"
#include "rangekit/core/family.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/record/capture.hpp"
#include "rangekit/record/replay.hpp"
#include "rangekit/uls/family.hpp"
#include "record/temp_dir.hpp"
#include "web/sample_aggregate.hpp"

namespace {

using namespace rangekit;
using namespace std::chrono_literals;

struct Expected {
  std::optional<double> value;  // none: a gap
  std::string unit;
  std::string channel;
};

struct Case {
  std::string name;
  Sample sample;
  Expected expected;
};

Sample base(const char* device, SampleKind kind, int second) {
  Sample sample;
  sample.time = std::chrono::system_clock::time_point{} + std::chrono::seconds(1'800'000'000 + second);
  sample.device = device;
  sample.source = "/dev/ttyUSB0";
  sample.kind = kind;
  return sample;
}

// Typed in by hand (U107): ULS §2 ("In Binning Mode you can choose to display the first target the
// laser sees"), LS5 §8.8 (the derivative, formula 8.2) and §8.9 (65535, no signal).
std::vector<Case> cases() {
  std::vector<Case> all;
  Sample averaging = base("uls", uls::kind::averaging, 0);
  averaging.set(uls::channel::distance_m, 12.345);
  averaging.set(uls::channel::pulse_width_ps, 4200);
  all.push_back({"averaging", averaging, {12.345, "m", "distance_m"}});
  Sample binning = base("uls", uls::kind::binning, 1);
  binning.targets = {{7.5, 12}, {3.25, 40}, {19.0, 9}};
  all.push_back({"binning burst of 3", binning, {3.25, "m", "targets"}});
  Sample derivative = base("ls5", ls5::kind::derivative, 2);
  derivative.set(ls5::channel::code, 1000);
  derivative.set(ls5::channel::derivative_mm, -0.5);
  derivative.set(ls5::channel::signal, ls5::SignalState::ok);
  all.push_back({"derivative", derivative, {-0.5, "mm", "derivative_mm"}});
  Sample edge = base("uls", uls::kind::look_down, 3);
  edge.set(uls::channel::presence, true);
  all.push_back({"look-down edge", edge, {1.0, "", "presence"}});
  Sample no_target = base("uls", uls::kind::error, 4);
  no_target.set(uls::channel::error, 4);  // §10: Lock Not Found (display: Target Not Found)
  all.push_back({"no target", no_target, {std::nullopt, "", ""}});
  Sample no_signal = base("ls5", ls5::kind::result, 5);
  no_signal.set(ls5::channel::code, 65535);
  no_signal.set(ls5::channel::signal, ls5::SignalState::lost);
  all.push_back({"LS5 no signal", no_signal, {std::nullopt, "", ""}});
  return all;
}

void expect_reading(const std::optional<Reading>& reading, const Case& c, const char* face) {
  SCOPED_TRACE(std::string(face) + ": " + c.name);
  ASSERT_EQ(reading.has_value(), c.expected.value.has_value());
  if (!reading) return;
  EXPECT_DOUBLE_EQ(reading->value, *c.expected.value);
  EXPECT_EQ(unit_symbol(reading->channel->unit), c.expected.unit);
  EXPECT_EQ(reading->channel->key, c.expected.channel);
}

// The cases' samples as a capture file (closed, so every one is committed).
::testing::AssertionResult write_capture(const std::string& path, const std::vector<Case>& all) {
  auto capture = record::open_capture(path);
  if (!capture.ok()) return ::testing::AssertionFailure() << capture.error().message;
  for (const Case& c : all) {
    if (auto written = (*capture)->write(c.sample); !written) {
      return ::testing::AssertionFailure() << c.name << ": " << written.error().message;
    }
  }
  if (auto flushed = (*capture)->flush(); !flushed) return ::testing::AssertionFailure() << flushed.error().message;
  return ::testing::AssertionSuccess();
}

TEST(SameReading, TheCaptureReplaysEachSampleWithItsReading) {
  record::testing::TempDir dir;
  const std::string path = dir.file("same.sqlite");
  const auto all = cases();
  ASSERT_TRUE(write_capture(path, all));
  std::vector<Sample> replayed;
  ASSERT_TRUE(record::for_each_in_capture(
                  path, "", [&](const Sample& sample) { replayed.push_back(sample); }, [](StreamEvent&&) {})
                  .ok());
  ASSERT_EQ(replayed.size(), all.size());
  for (std::size_t i = 0; i < all.size(); ++i) expect_reading(reading_of(replayed[i]), all[i], "capture");
}

nlohmann::json sse_aggregate_of(const Sample& sample) {
  web::SampleAggregate aggregate;
  aggregate.add(sample, 1);
  std::string event;
  aggregate.append_event(event, "belt");
  return nlohmann::json::parse(event.substr(event.find("data: ") + 6))["data"];
}

TEST(SameReading, AnSseAggregateReportsEachReading) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const auto data = sse_aggregate_of(c.sample);
    if (!c.expected.value) {
      EXPECT_EQ(data["gaps"], 1) << data.dump();
      EXPECT_FALSE(data.contains("last")) << data.dump();
      continue;
    }
    EXPECT_EQ(data["gaps"], 0) << data.dump();
    EXPECT_DOUBLE_EQ(data["last"].get<double>(), *c.expected.value);
    EXPECT_EQ(data["unit"], c.expected.unit);
    EXPECT_EQ(data["channel"], c.expected.channel);
  }
}

TEST(SameReading, AnMqttWindowReportsEachReading) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    mqtt::ReadingWindow window(10);
    const auto start = mqtt::ReadingWindow::Clock::now();
    ASSERT_TRUE(window.add(c.sample, start));  // the first goes out alone, at once
    EXPECT_FALSE(window.add(c.sample, start + 10ms));
    EXPECT_FALSE(window.add(c.sample, start + 20ms));  // two: a window, not a sample's own message
    const auto text = window.flush_due(start + 100ms);
    ASSERT_TRUE(text);
    const auto json = nlohmann::json::parse(*text);
    ASSERT_EQ(json["window"], true) << json.dump();
    if (!c.expected.value) {
      EXPECT_EQ(json["readings"], 0) << json.dump();
      EXPECT_TRUE(json["last"].is_null()) << json.dump();
      continue;
    }
    EXPECT_EQ(json["readings"], 2) << json.dump();
    EXPECT_DOUBLE_EQ(json["last"].get<double>(), *c.expected.value);
    EXPECT_DOUBLE_EQ(json["mean"].get<double>(), *c.expected.value);
    EXPECT_EQ(json["unit"], c.expected.unit);
    EXPECT_EQ(json["channel"], c.expected.channel);
  }
}

// Python reads the capture twice: as Sample objects (reading, unit, channel) and as the NumPy
// array, whose distance_m is the reading in metres when the reading is a length, NaN otherwise.
TEST(SameReading, PythonReportsEachReading) {
  if (*test::python_executable() == '\0') GTEST_SKIP() << "this build has no Python package";
  record::testing::TempDir dir;
  const std::string path = dir.file("same.sqlite");
  const auto all = cases();
  ASSERT_TRUE(write_capture(path, all));
  const std::string script =
      "import json, math, sys, rangekit\n"
      "objects = rangekit.capture.sample_objects(sys.argv[1])\n"
      "array = rangekit.capture.open(sys.argv[1]).samples\n"
      "print(json.dumps([[s.reading, s.reading_unit, s.reading_channel,\n"
      "                   None if math.isnan(a['distance_m']) else float(a['distance_m'])]\n"
      "                  for s, a in zip(objects, array)]))\n";
  const std::string script_path = dir.file("faces.py");
  record::testing::write_file(script_path, script);
  const std::string command = std::string("PYTHONPATH='") + test::python_path() + "' '" + test::python_executable() +
                              "' '" + script_path + "' '" + path + "' 2>&1";
  const auto run = cli_test::run_shell(command);
  const std::string& output = run.output;
  ASSERT_EQ(run.exit_code, 0) << output;
  const auto rows = nlohmann::json::parse(output);
  ASSERT_EQ(rows.size(), all.size()) << output;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Case& c = all[i];
    SCOPED_TRACE(c.name);
    const auto& row = rows[i];
    if (!c.expected.value) {
      EXPECT_TRUE(row[0].is_null() && row[1].is_null() && row[2].is_null() && row[3].is_null()) << row.dump();
      continue;
    }
    EXPECT_DOUBLE_EQ(row[0].get<double>(), *c.expected.value);
    EXPECT_EQ(row[1], c.expected.unit);
    EXPECT_EQ(row[2], c.expected.channel);
    const double metres = c.expected.unit == "mm" ? *c.expected.value / 1000 : *c.expected.value;
    if (c.expected.unit.empty()) {
      EXPECT_TRUE(row[3].is_null()) << "presence is no length: " << row.dump();
    } else {
      EXPECT_DOUBLE_EQ(row[3].get<double>(), metres);
    }
  }
}

}  // namespace
