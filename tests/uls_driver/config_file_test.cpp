// A config file that is not TOML: the error names the file and the line (docs/host-uls.md
// "Config files": "errors name the file, line and key").
#include <gtest/gtest.h>

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
  EXPECT_EQ(config.error().message, "nul.toml:2: 'mo\\x00de' is not a ULS setting (see `rangekit uls get`)");
}

// Refused alike by the LS5: nothing to load is an error, not "0 written".
TEST(UlsConfigFile, EmptyFileIsRefused) {
  const auto config = config_from_toml("", "empty.toml");
  ASSERT_FALSE(config);
  EXPECT_EQ(config.error().message, "empty.toml: no [settings] table");
}

}  // namespace
}  // namespace rangekit::uls
