// The readable settings catalog covers table 9.2 exactly once, and text <-> bytes
// round trips through it for every canonical setting at its default.
#include <gtest/gtest.h>

#include <map>

#include "rangekit/ls5/host_settings.hpp"

using namespace rangekit;
using namespace rangekit::ls5;

TEST(Ls5HostSettings, EveryTable92ByteBelongsToExactlyOneCanonicalSetting) {
  std::map<std::uint8_t, int> owners;
  for (const HostSetting& setting : host_setting_table()) {
    if (!setting.canonical) continue;
    for (const std::uint8_t address : setting.addresses()) ++owners[address];
  }
  for (const ParameterInfo& parameter : parameter_table()) {
    EXPECT_EQ(owners[parameter.address], 1) << hex_byte(parameter.address);
    const HostSetting* owner = host_setting_for_parameter(parameter.address);
    ASSERT_NE(owner, nullptr) << hex_byte(parameter.address);
  }
  EXPECT_EQ(owners.size(), parameter_table().size());
}

TEST(Ls5HostSettings, DefaultsRoundTripThroughText) {
  SettingContext context{SensorModel{firmware_12_x, true}, 40.001};
  for (const HostSetting& setting : host_setting_table()) {
    std::vector<std::uint8_t> bytes;
    for (const std::uint8_t address : setting.addresses()) bytes.push_back(default_byte(*find_parameter(address), 157));
    auto text = format_setting(setting, bytes, context);
    ASSERT_TRUE(text) << setting.name << ": " << text.error().message;
    auto writes = encode_setting(setting, *text, context);
    ASSERT_TRUE(writes) << setting.name << "=" << *text << ": " << writes.error().message;
    if (setting.form == SettingForm::value_mm || setting.form == SettingForm::value_range_mm) continue;  // rounded
    ASSERT_EQ(writes->count, bytes.size()) << setting.name;
    for (std::size_t i = 0; i < bytes.size(); ++i) {
      EXPECT_EQ(writes->items[i].value, bytes[i]) << setting.name;
    }
  }
}

// docs/conformance.md L48
TEST(Ls5HostSettings, Table92ExamplesInReadableUnits) {
  const SettingContext context{SensorModel{firmware_6_0, false}, std::nullopt};
  // Table 9.2: t = 1 ms is 000A, t = 5.2 ms is 0034; tau = 10 ms is 000A.
  auto period = encode_setting(*find_host_setting("period-ms"), "5.2", context);
  ASSERT_TRUE(period) << period.error().message;
  EXPECT_EQ(period->items[0], (ParameterWrite{0x06, 0x34}));
  EXPECT_EQ(period->items[1], (ParameterWrite{0x07, 0x00}));
  auto tau = encode_setting(*find_host_setting("signal-absence-ms"), "10", context);
  ASSERT_TRUE(tau) << tau.error().message;
  EXPECT_EQ(tau->items[0], (ParameterWrite{0x09, 0x0A}));
  // L4: m = 25 points is byte 0x19.
  auto median = encode_setting(*find_host_setting("median-points"), "25", context);
  ASSERT_TRUE(median) << median.error().message;
  EXPECT_EQ(median->items[0], (ParameterWrite{0x0D, 0x19}));
  // The mm forms need the range.
  auto mm = encode_setting(*find_host_setting("analog-lower-mm"), "1", context);
  ASSERT_FALSE(mm);
  EXPECT_NE(mm.error().message.find("range"), std::string::npos) << mm.error().message;
}
