// Who may connect, as a site file names it: dotted IPv4 addresses and ranges.
#include "rangekit/core/address_range.hpp"

#include <gtest/gtest.h>

namespace {

using rangekit::parse_address_range;
using rangekit::parse_ipv4;

TEST(AddressRange, ARangeHoldsTheAddressesItsPrefixCovers) {
  const auto private_a = parse_address_range("10.0.0.0/8");
  ASSERT_TRUE(private_a.ok());
  EXPECT_TRUE(private_a->contains(*parse_ipv4("10.255.1.2")));
  EXPECT_FALSE(private_a->contains(*parse_ipv4("11.0.0.1")));
  const auto one = parse_address_range("192.168.1.7");  // an address alone is a /32
  ASSERT_TRUE(one.ok());
  EXPECT_TRUE(one->contains(*parse_ipv4("192.168.1.7")));
  EXPECT_FALSE(one->contains(*parse_ipv4("192.168.1.8")));
  const auto everyone = parse_address_range("0.0.0.0/0");
  ASSERT_TRUE(everyone.ok());
  EXPECT_TRUE(everyone->contains(*parse_ipv4("203.0.113.9")));
}

TEST(AddressRange, AnythingButDottedIpv4IsRefusedNamingIt) {
  EXPECT_EQ(parse_ipv4("1.2.3.4"), 0x01020304U);
  for (const char* text : {"1.2.3", "1.2.3.4.5", "256.1.1.1", "1.2.3.-4", "a.b.c.d", "", "1..2.3", "::1"}) {
    EXPECT_FALSE(parse_ipv4(text)) << text;
  }
  const auto prefix = parse_address_range("10.0.0.0/33");
  ASSERT_FALSE(prefix.ok());
  EXPECT_EQ(prefix.error().message, "'10.0.0.0/33': the prefix is not 0-32");
  EXPECT_FALSE(parse_address_range("10.0.0.0/").ok());
  EXPECT_FALSE(parse_address_range("10.0.0.1/24").ok());  // host bits set
}

}  // namespace
