// The line protocol's escaping, the expected lines typed by hand from the InfluxDB line
// protocol reference ("Special characters": measurement: comma and space; tag keys, tag
// values and field keys: comma, equals sign and space; string field values: double quote
// and backslash, each escaped with a backslash).
#include "rangekit/sinks/line_protocol.hpp"

#include <gtest/gtest.h>

namespace {

using namespace rangekit::sinks;

TEST(LineProtocol, EscapesTagsPerTheReference) {
  EXPECT_EQ(escape_tag("bay A"), R"(bay\ A)");
  EXPECT_EQ(escape_tag("belt,2"), R"(belt\,2)");
  EXPECT_EQ(escape_tag("x=1"), R"(x\=1)");
  EXPECT_EQ(escape_tag("a b,c=d"), R"(a\ b\,c\=d)");
  EXPECT_EQ(escape_tag("plain-name_7"), "plain-name_7");
  // A double quote needs no escape in a tag.
  EXPECT_EQ(escape_tag(R"(say "hi")"), R"(say\ "hi")");
}

TEST(LineProtocol, EscapesMeasurementsWithoutTheEqualsSign) {
  EXPECT_EQ(escape_measurement("my measurement"), R"(my\ measurement)");
  EXPECT_EQ(escape_measurement("a,b=c"), R"(a\,b=c)");
}

TEST(LineProtocol, EscapesStringFieldValues) {
  EXPECT_EQ(escape_field_string(R"(He said "hi")"), R"(He said \"hi\")");
  EXPECT_EQ(escape_field_string(R"(C:\data)"), R"(C:\\data)");
  EXPECT_EQ(escape_field_string("a b,c=d"), "a b,c=d");  // nothing else inside quotes
}

TEST(LineProtocol, WritesOneReadingALine) {
  SinkReading reading;
  reading.sensor = "bay A,1=x";
  reading.family = "uls";
  reading.unit = "m";
  reading.value = 1.25;
  reading.suspect = true;
  reading.seq = 17;
  reading.time_ns = 1700000000123456789;
  EXPECT_EQ(encode_line(reading),
            "rangekit,family=uls,sensor=bay\\ A\\,1\\=x,unit=m value=1.25,suspect=true,seq=17i 1700000000123456789\n");
}

TEST(LineProtocol, LeavesAnEmptyUnitOutAndKeepsEveryDigit) {
  SinkReading reading;
  reading.sensor = "belt";
  reading.family = "ls5";
  reading.value = 15.718792959999998;
  reading.seq = 1;
  reading.time_ns = 5;
  EXPECT_EQ(encode_line(reading), "rangekit,family=ls5,sensor=belt value=15.718792959999998,suspect=false,seq=1i 5\n");
}

TEST(LineProtocol, NeverWritesALineBreakInsideALine) {
  SinkReading reading;
  reading.sensor = "two\nlines";
  reading.family = "uls";
  const std::string line = encode_line(reading);
  EXPECT_EQ(line.find('\n'), line.size() - 1) << line;
}

}  // namespace
