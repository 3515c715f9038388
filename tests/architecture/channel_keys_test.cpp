// A channel's key is the key its samples carry, and a number's key ends in its unit: what the
// API's family descriptors say (GET /api/families) is what jsonl, csv, SSE and MQTT print
// (docs/cli.md, "One vocabulary").
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "rangekit/core/family.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/record/format.hpp"
#include "rangekit/uls/family.hpp"

namespace {

using namespace rangekit;

Sample base(const char* device, SampleKind kind) {
  Sample sample;
  sample.device = device;
  sample.source = "/dev/ttyUSB0";
  sample.kind = kind;
  return sample;
}

// One sample of every kind, each value filled (typed in by hand: ULS §9 lines, LS5 §8.9 codes).
std::vector<Sample> every_kind() {
  std::vector<Sample> all;
  Sample averaging = base("uls", uls::kind::averaging);
  averaging.set(uls::channel::distance_m, 50.0);
  averaging.set(uls::channel::pulse_width_ps, 33238);  // §9 "yyyyyyy = pulse width (pico seconds)"
  all.push_back(averaging);
  Sample binning = base("uls", uls::kind::binning);
  binning.targets = {{4.572, 42}};
  all.push_back(binning);
  Sample edge = base("uls", uls::kind::look_down);
  edge.set(uls::channel::presence, true);
  edge.set(uls::channel::pulses_between_events, 250);
  all.push_back(edge);
  Sample error = base("uls", uls::kind::error);
  error.set(uls::channel::error, 4);
  all.push_back(error);
  Sample result = base("ls5", ls5::kind::result);
  result.set(ls5::channel::code, 25000);
  result.set(ls5::channel::distance_mm, 20.0005);
  result.set(ls5::channel::signal, ls5::SignalState::ok);
  all.push_back(result);
  Sample derivative = base("ls5", ls5::kind::derivative);
  derivative.set(ls5::channel::code, 25050);
  derivative.set(ls5::channel::derivative_mm, 0.1);
  derivative.set(ls5::channel::signal, ls5::SignalState::ok);
  all.push_back(derivative);
  return all;
}

nlohmann::json line_of(const Sample& sample) {
  std::string line;
  record::append_jsonl(line, sample);
  return nlohmann::json::parse(line);
}

TEST(ChannelKeys, EveryChannelIsAKeyItsFamilysSamplesCarry) {
  ASSERT_FALSE(families().empty());
  for (const FamilyDescriptor* family : families()) {
    std::set<std::string> keys;
    for (const Sample& sample : every_kind()) {
      if (sample.device != family->name) continue;
      const nlohmann::json line = line_of(sample);
      for (const auto& [key, value] : line.items()) keys.insert(key);
    }
    for (const ChannelDescriptor& channel : family->channels) {
      if (!channel.in_stream) continue;  // kept in captures only
      EXPECT_TRUE(keys.contains(std::string(channel.key))) << family->name << ": channel " << channel.key;
    }
  }
}

TEST(ChannelKeys, ANumbersKeyEndsInItsChannelsUnit) {
  for (const Sample& sample : every_kind()) {
    const FamilyDescriptor* family = find_family(sample.device);
    ASSERT_NE(family, nullptr) << sample.device;
    const nlohmann::json line = line_of(sample);
    for (const auto& [key, value] : line.items()) {
      const ChannelDescriptor* channel = find_channel(*family, key);
      if (channel == nullptr || !value.is_number()) continue;
      const std::string unit = unit_symbol(channel->unit);
      if (unit.empty()) continue;
      EXPECT_TRUE(key.ends_with("_" + unit)) << sample.device << ": " << key << " is in " << unit;
    }
  }
}

// U92: §8 tells the reader nanoseconds, §9 sends integer picoseconds; the key says ns and
// the value is ns, exact to the picosecond.
TEST(ChannelKeys, U92_ThePulseWidthIsNanosecondsUnderANameThatSaysSo) {
  const Sample averaging = every_kind().front();
  const FamilyDescriptor* family = find_family(averaging.device);
  ASSERT_NE(family, nullptr);
  const ChannelDescriptor* width = find_channel(*family, "pulse_width_ns");
  ASSERT_NE(width, nullptr);
  EXPECT_EQ(width->quantity, Quantity::pulse_width);
  EXPECT_STREQ(unit_symbol(width->unit), "ns");
  std::string line;
  record::append_jsonl(line, averaging);
  EXPECT_NE(line.find("\"pulse_width_ns\":33.238}"), std::string::npos) << line;
}

}  // namespace
