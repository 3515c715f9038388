// Readable setting values mean what their names say: a bin size is a size, never a raw code
// read as one without a word (docs/cli.md, "One vocabulary").
#include <gtest/gtest.h>

#include "rangekit/uls/named_settings.hpp"

namespace {

using namespace rangekit;
using namespace rangekit::uls;

// §8 BS "n = 0 = 1 inch, n = 1 = 2 inches, n = 2 = 4 inches, ...": `bin-size=4` read as code 4
// would write 16 inches. A bare number is refused, naming the size it could mean and the code.
TEST(NamedValues, ABareNumberIsNoBinSize) {
  auto refused = named::plan({{"bin-size", "4"}});
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code, Errc::out_of_range);
  EXPECT_EQ(refused.error().message,
            "bin-size: '4' is not a bin size: give its unit, 4-inches (BS 2), or the code as BS=4");

  auto no_such_size = named::plan({{"bin-size", "5"}});
  ASSERT_FALSE(no_such_size.ok());
  EXPECT_EQ(no_such_size.error().message,
            "bin-size: '5' is not a bin size: give one of 1-inch, 2-inches, 4-inches, 8-inches, 16-inches, "
            "32-inches, 64-inches, 128-inches, 256-inches, or the code as BS=5");

  auto named = named::plan({{"bin-size", "4-inches"}});
  ASSERT_TRUE(named.ok()) << named.error().message;
  auto fields = named::to_fields(named->front().target, named->front().value, Units::metres);
  ASSERT_TRUE(fields.ok());
  EXPECT_EQ(*fields, std::vector<std::string>{"2"});

  auto code = named::plan({{"BS", "4"}});  // the mnemonic takes §8's code as it is
  ASSERT_TRUE(code.ok()) << code.error().message;
  fields = named::to_fields(code->front().target, code->front().value, Units::metres);
  ASSERT_TRUE(fields.ok());
  EXPECT_EQ(*fields, std::vector<std::string>{"4"});
}

// Codes stay codes where the values are words: `mode=2` is binning (§8 MM "n = 2").
TEST(NamedValues, ACodeOfAWordedSettingIsStillItsCode) {
  auto mode = named::plan({{"mode", "2"}});
  ASSERT_TRUE(mode.ok()) << mode.error().message;
  auto fields = named::to_fields(mode->front().target, mode->front().value, Units::metres);
  ASSERT_TRUE(fields.ok());
  EXPECT_EQ(*fields, std::vector<std::string>{"2"});
}

// §8 RS485 Protocol: a unit address is a byte 0x30-0xEF; the UA get reply carries it as a
// number. `get` spells it as the family does everywhere, so that `set address=` takes it back:
// 'A' for 65, and 0x9C for a byte no terminal shows (it printed 156).
TEST(NamedValues, AnAddressReadsAsSetTakesIt) {
  const CommandInfo& ua = command_info(CommandId::address);
  EXPECT_EQ(named::describe_reply(ua, {"65"}, Units::metres).text, "A");
  EXPECT_EQ(named::describe_reply(ua, {"156"}, Units::metres).text, "0x9C");
  auto planned = named::plan({{"address", "0x9C"}});
  ASSERT_TRUE(planned.ok()) << planned.error().message;
  auto fields = named::to_fields(planned->front().target, planned->front().value, Units::metres);
  ASSERT_TRUE(fields.ok()) << fields.error().message;
  EXPECT_EQ(*fields, std::vector<std::string>{std::string(1, '\x9C')});  // the byte itself on the wire
}

}  // namespace
