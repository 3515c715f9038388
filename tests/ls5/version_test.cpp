// Firmware versions as §9.2 (identification) and table 9.2 notes write them.
#include <gtest/gtest.h>

#include "rangekit/ls5/version.hpp"

using namespace rangekit;
using namespace rangekit::ls5;

TEST(Ls5Version, ParsesTheDocumentsForms) {
  const auto v6 = parse_firmware_version("LS5.6.0");  // §9.2 example
  ASSERT_TRUE(v6.ok()) << v6.error().describe();
  EXPECT_EQ(v6->major, 6);
  EXPECT_EQ(v6->minor, 0);
  EXPECT_FALSE(v6->any_minor);
  EXPECT_EQ(v6->to_string(), "LS5.6.0");

  const auto v12 = parse_firmware_version("LS5.12.x");  // table 9.2 note 5
  ASSERT_TRUE(v12.ok());
  EXPECT_EQ(v12->major, 12);
  EXPECT_TRUE(v12->any_minor);
  EXPECT_EQ(v12->to_string(), "LS5.12.x");
  EXPECT_EQ(*v12, firmware_12_x);

  EXPECT_EQ(parse_firmware_version("LS5.9.13").value_or(FirmwareVersion{}), (FirmwareVersion{9, 13}));
  EXPECT_EQ(try_parse_firmware_version("LS5.7.0"), firmware_7_0);
}

TEST(Ls5Version, Ordering) {
  EXPECT_LT(firmware_6_0, firmware_7_0);
  EXPECT_LT((FirmwareVersion{9, 0}), (FirmwareVersion{12, 0}));  // numeric, not text, order
  EXPECT_LT((FirmwareVersion{6, 2}), (FirmwareVersion{6, 10}));
  EXPECT_TRUE((FirmwareVersion{12, 3}).at_least(firmware_12_x));  // "LS5.12.x" covers every 12 release
  EXPECT_FALSE((FirmwareVersion{11, 99}).at_least(firmware_12_x));
  EXPECT_TRUE(firmware_6_0.at_least(any_firmware));
  EXPECT_FALSE(any_firmware.at_least(firmware_6_0));
}

TEST(Ls5Version, RejectsOtherText) {
  for (const std::string_view text : {"", "LS5", "LS5.", "LS5.6", "LS5.6.", "LS5..0", "LS4.6.0", "ls5.6.0", "LS5.6.0 ",
                                      " LS5.6.0", "LS5.6.0.1", "LS5.1000.0", "LS5.x.0", "LS5.-1.0"}) {
    const auto version = parse_firmware_version(text);
    ASSERT_FALSE(version.ok()) << text;
    EXPECT_EQ(version.error().code, Errc::bad_number);
    EXPECT_NE(version.error().message.find("LS5 firmware version"), std::string::npos);
    EXPECT_FALSE(try_parse_firmware_version(text).has_value()) << text;
  }
}
