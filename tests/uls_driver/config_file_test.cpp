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

}  // namespace
}  // namespace rangekit::uls
