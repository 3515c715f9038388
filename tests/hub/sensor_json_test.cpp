// The sensor object both faces send (GET /api/sensors/{name}, MQTT's retained status): one
// spelling of a unit address in it, the family's, and the byte on the wire once.
#include "rangekit/hub/json_views.hpp"

#include <gtest/gtest.h>

namespace {

using namespace rangekit;
using namespace rangekit::hub;

SensorSnapshot sensor_at(std::string family, std::optional<int> address) {
  SensorSnapshot sensor;
  sensor.config.name = "unit";
  sensor.config.family = std::move(family);
  sensor.config.address = address;
  return sensor;
}

// §8 Set/Get Unit Address: the site file's `address = "A"` is the byte 65.
TEST(SensorJson, AUlsUnitAddressIsItsCharacterAsInItsIdentity) {
  auto unit = sensor_at("uls", 'A');
  unit.identity = {{"version", "ULS 1.0", ""}, {"address", "A", ""}};
  const auto json = sensor_json(unit);
  EXPECT_EQ(json["address"], "A");
  EXPECT_EQ(json["identity"]["address"], json["address"]);
  EXPECT_EQ(json["address_code"], 65);
}

// §8 RS485 Protocol: 0x30-0xEF; a byte a terminal cannot show is written in hex.
TEST(SensorJson, AUlsAddressWithoutACharacterIsHex) {
  const auto json = sensor_json(sensor_at("uls", 0x9C));
  EXPECT_EQ(json["address"], "0x9C");
  EXPECT_EQ(json["address_code"], 0x9C);
}

// Table 9.2 parameter 01, a number in the site file and in decimal wherever a person reads it.
TEST(SensorJson, AnLs5NetworkAddressIsDecimalTextOfTheSameType) {
  const auto json = sensor_json(sensor_at("ls5", 26));
  EXPECT_EQ(json["address"], "26");
  EXPECT_EQ(json["address_code"], 26);
}

TEST(SensorJson, ASensorWithoutAnAddressHasNeitherField) {
  const auto json = sensor_json(sensor_at("uls", std::nullopt));
  EXPECT_FALSE(json.contains("address"));
  EXPECT_FALSE(json.contains("address_code"));
}

}  // namespace
