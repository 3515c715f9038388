// The fast path's PUBLISH encoding (docs/mqtt.md) against the MQTT 5.0 standard's own
// numbers, typed in by hand: the Variable Byte Integer table of §1.5.5 (Table 1-1, both
// ends of every size) and a QoS 0 PUBLISH laid out by §3.3 (fixed header 3.3.1, Topic
// Name 3.3.2.1, Property Length 3.3.2.3, payload 3.3.3).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "mqtt/publish_packet.hpp"

namespace {

using rangekit::mqtt::append_publish_qos0;
using rangekit::mqtt::append_variable_byte_integer;
using rangekit::mqtt::publish_packet_size;

std::vector<unsigned> bytes_of(const std::string& text) {
  std::vector<unsigned> bytes;
  for (const char c : text) bytes.push_back(static_cast<unsigned char>(c));
  return bytes;
}

std::vector<unsigned> vbi(std::uint32_t value) {
  std::string out;
  append_variable_byte_integer(out, value);
  return bytes_of(out);
}

TEST(PublishPacket, VariableByteIntegerMatchesTable1_1) {
  EXPECT_EQ(vbi(0), (std::vector<unsigned>{0x00}));
  EXPECT_EQ(vbi(127), (std::vector<unsigned>{0x7F}));
  EXPECT_EQ(vbi(128), (std::vector<unsigned>{0x80, 0x01}));
  EXPECT_EQ(vbi(16'383), (std::vector<unsigned>{0xFF, 0x7F}));
  EXPECT_EQ(vbi(16'384), (std::vector<unsigned>{0x80, 0x80, 0x01}));
  EXPECT_EQ(vbi(2'097'151), (std::vector<unsigned>{0xFF, 0xFF, 0x7F}));
  EXPECT_EQ(vbi(2'097'152), (std::vector<unsigned>{0x80, 0x80, 0x80, 0x01}));
  EXPECT_EQ(vbi(268'435'455), (std::vector<unsigned>{0xFF, 0xFF, 0xFF, 0x7F}));
}

TEST(PublishPacket, Qos0PublishIsHeaderTopicEmptyPropertiesPayload) {
  std::string out;
  ASSERT_TRUE(append_publish_qos0(out, "a/b", "hi", false));
  // 0x30: PUBLISH, DUP 0, QoS 0, RETAIN 0. Remaining Length 8 = 2 + 3 (topic) + 1 (properties) + 2.
  const std::vector<unsigned> expected{0x30, 0x08, 0x00, 0x03, 'a', '/', 'b', 0x00, 'h', 'i'};
  EXPECT_EQ(bytes_of(out), expected);
  EXPECT_EQ(publish_packet_size("a/b", "hi"), expected.size());

  std::string retained;
  ASSERT_TRUE(append_publish_qos0(retained, "a/b", "", true));
  EXPECT_EQ(bytes_of(retained), (std::vector<unsigned>{0x31, 0x06, 0x00, 0x03, 'a', '/', 'b', 0x00}));
}

TEST(PublishPacket, RemainingLengthCrossesToTwoBytesAt128) {
  // Topic "t" (2 + 1) and the property length (1): a payload of 123 gives 127, of 124 gives 128.
  std::string out;
  ASSERT_TRUE(append_publish_qos0(out, "t", std::string(123, 'x'), false));
  EXPECT_EQ(static_cast<unsigned char>(out[1]), 0x7FU);
  EXPECT_EQ(out.size(), 1 + 1 + 127U);
  out.clear();
  ASSERT_TRUE(append_publish_qos0(out, "t", std::string(124, 'x'), false));
  EXPECT_EQ(static_cast<unsigned char>(out[1]), 0x80U);
  EXPECT_EQ(static_cast<unsigned char>(out[2]), 0x01U);
  EXPECT_EQ(out.size(), 1 + 2 + 128U);
  EXPECT_EQ(publish_packet_size("t", std::string(124, 'x')), out.size());
}

TEST(PublishPacket, ATopicLongerThanAnEncodedStringIsRefused) {
  std::string out = "kept";
  EXPECT_FALSE(append_publish_qos0(out, std::string(65'536, 'a'), "x", false));  // §1.5.4: at most 65,535 bytes
  EXPECT_EQ(out, "kept");
  EXPECT_EQ(publish_packet_size(std::string(65'536, 'a'), "x"), 0U);
  EXPECT_GT(publish_packet_size(std::string(65'535, 'a'), "x"), 0U);
}

}  // namespace
