// A config file that is not TOML: docs/host-ls5.md, "invalid_frame with file and line for
// TOML errors".
#include <gtest/gtest.h>

#include "rangekit/ls5/host_config.hpp"

namespace rangekit::ls5 {
namespace {

TEST(Ls5ConfigFile, SyntaxErrorNamesFileAndLine) {
  const auto config = parse_config_toml("[sensor]\naddress = \n", "bad.toml");
  ASSERT_FALSE(config);
  EXPECT_EQ(config.error().code, Errc::invalid_frame);
  EXPECT_EQ(config.error().message.rfind("bad.toml:2: ", 0), 0u) << config.error().message;
}

}  // namespace
}  // namespace rangekit::ls5
