// A config file that is not TOML: the error names the file and the line (docs/host-uls.md
// "Config files": "errors name the file, line and key").
#include <gtest/gtest.h>

#include <algorithm>

#include "rangekit/uls/formulas.hpp"
#include "rangekit/uls/host_config.hpp"

namespace rangekit::uls {
namespace {

TEST(UlsConfigFile, SyntaxErrorNamesFileAndLine) {
  const auto config = config_from_toml("[settings]\nmode = \n", "bad.toml");
  ASSERT_FALSE(config);
  EXPECT_EQ(config.error().code, Errc::invalid_frame);
  EXPECT_EQ(config.error().message.rfind("bad.toml:2: ", 0), 0u) << config.error().message;
}

// A NUL in a TOML key is printed escaped, never raw.
TEST(UlsConfigFile, NulInAKeyIsPrintedEscaped) {
  const auto config = config_from_toml("[settings]\n\"mo\\u0000de\" = 1\n", "nul.toml");
  ASSERT_FALSE(config);
  EXPECT_EQ(config.error().message.find('\0'), std::string::npos);
  EXPECT_EQ(config.error().message.rfind("nul.toml:2: 'mo\\x00de' is not a ULS setting; did you mean 'mode'?", 0), 0U)
      << config.error().message;
}

// Refused alike by the LS5: nothing to load is an error, not "0 written".
TEST(UlsConfigFile, EmptyFileIsRefused) {
  const auto config = config_from_toml("", "empty.toml");
  ASSERT_FALSE(config);
  EXPECT_EQ(config.error().message, "empty.toml: no [settings] table");
}

// The value a loaded file holds for one mnemonic, or none.
std::vector<double> values_of(const DeviceConfig& config, std::string_view mnemonic) {
  const auto found = std::find_if(config.settings.begin(), config.settings.end(),
                                  [&](const Setting& setting) { return setting.command->mnemonic == mnemonic; });
  return found == config.settings.end() ? std::vector<double>{} : found->values;
}

// A saved file speaks `get`'s names and values: the unit in the name, the time in seconds,
// flags as get prints them (docs/cli.md "One vocabulary").
TEST(UlsConfigFile, ASavedFileUsesTheNamesAndValuesOfGet) {
  const std::string text = config_to_toml(factory_config(), "test");
  for (const char* line : {"long-gate-m = 0.0  # LG", "short-gate-m = 0.0  # SG", "offset-m = 0.0  # OF",
                           "trip-timeout-s = 360.0  # TT", "fault-current-ma = 3.0  # AF", "continuous = \"on\"  # CO",
                           "prf-hz = [2000, 2000, 2000]  # PF", "mode = \"averaging\"  # MM"})
    EXPECT_NE(text.find(std::string("\n") + line), std::string::npos) << line << "\n" << text;
  auto back = config_from_toml(text, "saved.toml");
  ASSERT_TRUE(back) << back.error().message;
  ASSERT_EQ(back->settings.size(), factory_config().settings.size());
  for (std::size_t i = 0; i < back->settings.size(); ++i) {
    EXPECT_EQ(back->settings[i].command, factory_config().settings[i].command);
    EXPECT_EQ(back->settings[i].values, factory_config().settings[i].values) << back->settings[i].command->mnemonic;
  }
}

// The names `get` prints load, each in the unit its name says.
TEST(UlsConfigFile, GetsNamesLoadInTheUnitTheirNameSays) {
  auto config = config_from_toml(
      "[settings]\nlong-gate-m = 1.0\nshort-gate-m = 0.5\noffset-m = -0.25\nfault-timeout-s = 2\n"
      "trip-timeout-s = 10\ncontinuous = \"off\"\nprf-hz = [1000, 1000, 1000]\nbin-size = \"4-inches\"\n",
      "named.toml");
  ASSERT_TRUE(config) << config.error().message;
  EXPECT_EQ(values_of(*config, "LG"), std::vector<double>{1.0});
  EXPECT_EQ(values_of(*config, "SG"), std::vector<double>{0.5});
  EXPECT_EQ(values_of(*config, "OF"), std::vector<double>{-0.25});
  EXPECT_EQ(values_of(*config, "AT"), std::vector<double>{2.0});
  EXPECT_EQ(values_of(*config, "TT"), std::vector<double>{10.0 * trip_timeout_pulses_per_second});
  EXPECT_EQ(values_of(*config, "CO"), std::vector<double>{0});
  EXPECT_EQ(values_of(*config, "PF"), (std::vector<double>{1000, 1000, 1000}));
  EXPECT_EQ(values_of(*config, "BS"), std::vector<double>{2});
}

// A name that does not say its unit, or a bare number that could be a code or a quantity,
// is refused with the spelling that says what it means.
TEST(UlsConfigFile, AValueThatCouldMeanTwoThingsIsRefusedWithTheNameThatSaysWhich) {
  auto pulses = config_from_toml("[settings]\ntrip-timeout = 10\n", "old.toml");
  ASSERT_FALSE(pulses);
  EXPECT_EQ(pulses.error().message,
            "old.toml:2: 'trip-timeout' names no unit: write trip-timeout-s in seconds (pulses / 3000)");
  auto code = config_from_toml("[settings]\nbin-size = 4\n", "code.toml");
  ASSERT_FALSE(code);
  EXPECT_EQ(code.error().message, "code.toml:2: 'bin-size' '4' is not a bin size: give its unit, 4-inches (BS 2)");
  auto mnemonic = config_from_toml("[settings]\nTT = \"107AC0\"\n", "raw.toml");
  ASSERT_FALSE(mnemonic);
  EXPECT_EQ(mnemonic.error().message,
            "raw.toml:2: 'TT' is a mnemonic: a config file names it as `rangekit uls get` does, trip-timeout-s");
  auto address = config_from_toml("[settings]\naddress = \"A\"\n", "link.toml");
  ASSERT_FALSE(address);
  EXPECT_NE(address.error().message.find("link.toml:2: 'address' is not kept in a config file"), std::string::npos)
      << address.error().message;
  auto typo = config_from_toml("[settings]\nlong-gate-mm = 1.0\n", "typo.toml");
  ASSERT_FALSE(typo);
  EXPECT_NE(typo.error().message.find("typo.toml:2: 'long-gate-mm' is not a ULS setting; did you mean 'long-gate-m'"),
            std::string::npos)
      << typo.error().message;
}

}  // namespace
}  // namespace rangekit::uls
