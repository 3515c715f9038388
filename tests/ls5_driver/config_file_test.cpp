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

// A file with no [link] or [parameters] setting is refused, as the ULS refuses an empty
// one, rather than reported as "0 settings written, verified".
TEST(Ls5ConfigFile, EmptyFileIsRefusedAsTheUlsRefusesIt) {
  for (const char* text : {"", "# nothing\n", "[sensor]\naddress = 3\n", "[parameters]\n"}) {
    const auto config = parse_config_toml(text, "empty.toml");
    ASSERT_FALSE(config) << text;
    EXPECT_EQ(config.error().code, Errc::invalid_frame);
    EXPECT_EQ(config.error().message, "empty.toml: no settings in [link] or [parameters]; nothing to load");
  }
}

// A NUL in a TOML key is not printed raw: keys and sections are printed
// with control characters escaped (\x00, \x1b).
TEST(Ls5ConfigFile, ControlCharactersInKeysArePrintedEscaped) {
  auto config = parse_config_toml("[parameters]\n\"lase\\u0000r\" = 1\n", "nul.toml");
  ASSERT_FALSE(config);
  EXPECT_EQ(config.error().message, "nul.toml:2: 'lase\\x00r' is not an LS5 setting");
  config = parse_config_toml("[\"\\u001b[2J\"]\nx = 1\n", "esc.toml");
  ASSERT_FALSE(config);
  EXPECT_EQ(config.error().message.find('\x1b'), std::string::npos) << config.error().message;
  EXPECT_NE(config.error().message.find("[\\x1b[2J]"), std::string::npos) << config.error().message;
}

}  // namespace
}  // namespace rangekit::ls5
