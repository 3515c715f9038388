// site.toml: what `rangekit serve --config` and `--check` accept and refuse (docs/service.md).
#include "rangekit/hub/site_config.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <algorithm>

#include <array>
#include <cstdio>
#include <fstream>
#include <string>

#include "ls5_driver/cli_process.hpp"

namespace {

using rangekit::Errc;
using rangekit::Parity;
using namespace rangekit::hub;

SiteConfig parse_ok(const std::string& text) {
  auto site = parse_site_config(text, "site.toml");
  EXPECT_TRUE(site.ok()) << (site.ok() ? "" : site.error().message);
  return site.ok() ? *site : SiteConfig{};
}

std::string refusal(const std::string& text) {
  auto site = parse_site_config(text, "site.toml");
  EXPECT_FALSE(site.ok()) << "accepted:\n" << text;
  return site.ok() ? "" : site.error().message;
}

TEST(SiteConfig, ReadsEveryKeyOfASensor) {
  const auto site = parse_ok(R"(
[service]
listen = "0.0.0.0:9000"
capture_dir = "/var/lib/rangekit"

[[sensor]]
name = "hopper-1"
family = "uls"
port = "/dev/ttyUSB0"
baud = 19200
address = "A"
stream = false
capture = true

[[sensor]]
name = "belt"
family = "ls5"
port = "/dev/ttyUSB1"
baud = 9600
format = "8E1"
address = 3

[[sensor]]
name = "eth"
family = "ls5"
udp = "0.0.0.0:5000"
)");
  ASSERT_EQ(site.sensors.size(), 3u);
  EXPECT_EQ(site.service.listen, "0.0.0.0:9000");
  EXPECT_EQ(site.service.capture_dir, "/var/lib/rangekit");
  const SensorConfig& uls = site.sensors[0];
  EXPECT_EQ(uls.name, "hopper-1");
  EXPECT_EQ(uls.family, "uls");
  EXPECT_EQ(uls.serial.baud, 19200u);
  EXPECT_EQ(uls.address, 0x41);  // §8 UA table: 'A' is 0x41
  EXPECT_FALSE(uls.stream);
  EXPECT_TRUE(uls.capture);
  EXPECT_EQ(uls.line, 6u);
  const SensorConfig& ls5 = site.sensors[1];
  EXPECT_EQ(ls5.family, "ls5");
  EXPECT_EQ(ls5.serial.parity, Parity::even);  // LS5 table 9.2 byte format 8E1
  EXPECT_EQ(ls5.serial.stop_bits, 1);
  EXPECT_EQ(ls5.address, 3);
  EXPECT_TRUE(ls5.stream);  // the default
  EXPECT_EQ(site.sensors[2].udp, "0.0.0.0:5000");
}

TEST(SiteConfig, AnRs485BusIsSeveralAddressedUlsOnOnePort) {
  const auto site = parse_ok(R"(
[[sensor]]
name = "a"
family = "uls"
port = "/dev/ttyUSB0"
address = "A"
[[sensor]]
name = "b"
family = "uls"
port = "/dev/ttyUSB0"
address = "0x42"
[[sensor]]
name = "c"
family = "uls"
port = "/dev/ttyUSB1"
)");
  const auto groups = port_groups(site);
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[0].sensors.size(), 2u);
  EXPECT_TRUE(groups[0].bus());
  EXPECT_FALSE(groups[1].bus());
  EXPECT_EQ(groups[0].sensors[1]->address, 0x42);
}

TEST(SiteConfig, RefusesWithFileLineAndReason) {
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\nspeed = 9600\n"),
            "site.toml:5: unknown key 'speed' in [[sensor]] (allowed: name, family, port, baud, format, address, udp, "
            "stream, capture, max_speed, drop_suspect, modbus_unit)");
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"lms\"\nport = \"/dev/x\"\n"),
            "site.toml:3: family 'lms' is not \"uls\" or \"ls5\"");
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a b\"\nfamily = \"uls\"\nport = \"/dev/x\"\n"),
            "site.toml:2: name 'a b' must be 1-64 letters, digits, '-' or '_' (it goes into URLs and topics)");
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\nbaud = 12\n"),
            "site.toml:5: baud 12 is not a baud of the ULS (1200, 2400, 4800, 9600, 14400, 19200, 38400, 57600, "
            "115200, 230400)");
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\nformat = \"8E1\"\n"),
            "site.toml:5: format '8E1': the ULS speaks 8N1 only");
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"ls5\"\nport = \"/dev/x\"\naddress = 0\n"),
            "site.toml:5: address 0 is out of range 1-255 (LS5 network address, parameter 01)");
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\naddress = \"!\"\n"),
            "site.toml:5: address '!' is not a ULS unit address (0x30-0xEF, e.g. \"A\" or \"0x41\")");
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nudp = \"0.0.0.0:5000\"\n"),
            "site.toml:4: udp is for LS5 Ethernet models only\nsite.toml:2: sensor 'a' needs a port");
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"uls\"\n"), "site.toml:2: sensor 'a' needs a port");
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"ls5\"\nport = \"/dev/x\"\nudp = \"0.0.0.0:1\"\n"),
            "site.toml:2: sensor 'a' has both a port and udp: give one (serial stream and commands, or the Ethernet "
            "stream alone)");
  EXPECT_EQ(refusal("[service]\nlisten = \"127.0.0.1:8080\"\n"),
            "site.toml: no sensors: add a [[sensor]] table for each");
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\nstream = \"yes\"\n"),
            "site.toml:5: stream must be true or false");
  EXPECT_EQ(refusal("[http]\n"),
            "site.toml:1: unknown key 'http' in the site file (allowed: service, mqtt, modbus, sensor, sink)");
  EXPECT_NE(refusal("[[sensor]]\nname = \n").find("site.toml:2:"), std::string::npos);  // TOML syntax
}

// [modbus] and each sensor's unit id (docs/modbus.md): a unit is the sensor's position unless given.
TEST(SiteConfig, ModbusTableAndUnitIds) {
  const std::string two =
      "[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\n"
      "[[sensor]]\nname = \"b\"\nfamily = \"uls\"\nport = \"/dev/y\"\nmodbus_unit = 12\n";
  const SiteConfig plain = parse_ok(two);
  EXPECT_TRUE(plain.modbus.listen.empty());
  EXPECT_EQ(plain.modbus.word_order, "ABCD");
  EXPECT_EQ(modbus_units(plain), (std::vector<std::pair<std::uint8_t, std::string>>{{1, "a"}, {12, "b"}}));
  EXPECT_EQ(parse_ok("[modbus]\nwritable = true\n" + two).modbus.listen, "127.0.0.1:5020");  // the table turns it on
  const SiteConfig set = parse_ok(
      "[modbus]\nlisten = \"0.0.0.0:502\"\nword_order = \"cdab\"\nwritable = true\nallow = [\"10.0.0.0/8\", "
      "\"192.168.1.7\"]\n" +
      two);
  EXPECT_EQ(set.modbus.listen, "0.0.0.0:502");
  EXPECT_EQ(set.modbus.word_order, "CDAB");
  EXPECT_TRUE(set.modbus.writable);
  EXPECT_EQ(set.modbus.allow, (std::vector<std::string>{"10.0.0.0/8", "192.168.1.7"}));
  EXPECT_EQ(refusal("[modbus]\nword_order = \"ABDC\"\n" + two),
            "site.toml:2: word_order 'ABDC' is not ABCD, CDAB, BADC or DCBA (A: the most significant byte)");
  EXPECT_EQ(refusal("[modbus]\nallow = [\"10.0.0.1/8\"]\n" + two),
            "site.toml:2: allow '10.0.0.1/8' has host bits set: a /8 range starts at a multiple of its size");
  EXPECT_EQ(refusal("[modbus]\nallow = [\"plant\"]\n" + two),
            "site.toml:2: allow 'plant' is not an IPv4 address or range (10.0.0.0/8)");
  EXPECT_EQ(refusal("[modbus]\nlisten = \"nowhere\"\n" + two).rfind("site.toml:2: listen 'nowhere'", 0), 0u);
  EXPECT_EQ(refusal("[modbus]\nport = 502\n" + two),
            "site.toml:2: unknown key 'port' in [modbus] (allowed: listen, word_order, writable, allow)");
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\nmodbus_unit = 248\n"),
            "site.toml:5: modbus_unit = 248: a Modbus unit id is 1 to 247");
  // b takes 1, which is a's by position.
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\n"
                    "[[sensor]]\nname = \"b\"\nfamily = \"uls\"\nport = \"/dev/y\"\nmodbus_unit = 1\n"),
            "site.toml:5: Modbus unit 1 of 'b' is also the unit of 'a' (a sensor without modbus_unit takes its "
            "position in the file)");
}

// How many captures run at once: 16 unless [service] says, from 1 to 1024.
TEST(SiteConfig, MaxCapturesIsCheckedAndDefaultsTo16) {
  const std::string sensor = "[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\n";
  EXPECT_EQ(parse_ok(sensor).service.max_captures, 16u);
  EXPECT_EQ(parse_ok("[service]\nmax_captures = 40\n" + sensor).service.max_captures, 40u);
  EXPECT_EQ(refusal("[service]\nmax_captures = 0\n" + sensor),
            "site.toml:2: max_captures = 0: captures running at once, 1 to 1024");
  EXPECT_EQ(refusal("[service]\nmax_captures = 5000\n" + sensor),
            "site.toml:2: max_captures = 5000: captures running at once, 1 to 1024");
  EXPECT_NE(refusal("[service]\nmax_captures = \"many\"\n" + sensor).find("site.toml:2:"), std::string::npos);
}

// U102, L71: per sensor, the fastest its target moves and whether suspect
// samples are left out; unset, the family default and kept.
TEST(SiteConfig, U102_L71_MaxSpeedAndDropSuspectPerSensor) {
  const auto site = parse_ok(
      "[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\nmax_speed = 2.5\ndrop_suspect = true\n"
      "[[sensor]]\nname = \"b\"\nfamily = \"ls5\"\nport = \"/dev/y\"\nmax_speed = 1\n"
      "[[sensor]]\nname = \"c\"\nfamily = \"ls5\"\nport = \"/dev/z\"\n");
  ASSERT_EQ(site.sensors.size(), 3u);
  EXPECT_EQ(site.sensors[0].max_speed_mps, 2.5);
  EXPECT_TRUE(site.sensors[0].drop_suspect);
  EXPECT_EQ(site.sensors[1].max_speed_mps, 1.0);
  EXPECT_FALSE(site.sensors[1].drop_suspect);
  EXPECT_FALSE(site.sensors[2].max_speed_mps.has_value());
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\nmax_speed = 0\n"),
            "site.toml:5: max_speed must be above 0 and at most 1e6 m/s");
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\nmax_speed = \"fast\"\n"),
            "site.toml:5: max_speed must be a number (metres per second)");
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\ndrop_suspect = 1\n"),
            "site.toml:5: drop_suspect must be true or false");
}

TEST(SiteConfig, RefusesTwoSensorsThatCannotShareAPort) {
  const std::string a = "[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/x\"\naddress = \"A\"\n";
  EXPECT_EQ(refusal(a + "[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/y\"\n"),
            "site.toml:6: sensor name 'a' is already used at line 1");
  EXPECT_EQ(
      refusal(a + "[[sensor]]\nname = \"b\"\nfamily = \"uls\"\nport = \"/dev/x\"\naddress = \"B\"\nbaud = 9600\n"),
      "site.toml:6: port /dev/x is also claimed by 'a' (line 1) with other settings (115200 8N1 there, 9600 "
      "8N1 here)");
  EXPECT_EQ(refusal(a + "[[sensor]]\nname = \"b\"\nfamily = \"uls\"\nport = \"/dev/x\"\n"),
            "site.toml:6: port /dev/x is also claimed by 'a' (line 1): units sharing an RS-485 port each need an "
            "address");
  EXPECT_EQ(refusal(a + "[[sensor]]\nname = \"b\"\nfamily = \"uls\"\nport = \"/dev/x\"\naddress = 65\n"),
            "site.toml:6: address of 'b' is also the address of 'a' (line 1) on port /dev/x (one unit per "
            "address)");
  EXPECT_EQ(refusal(a + "[[sensor]]\nname = \"b\"\nfamily = \"ls5\"\nport = \"/dev/x\"\n"),
            "site.toml:6: port /dev/x is also claimed by 'a' (line 1) as uls: one port carries one family");
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"ls5\"\nport = \"/dev/x\"\n"
                    "[[sensor]]\nname = \"b\"\nfamily = \"ls5\"\nport = \"/dev/x\"\naddress = 2\n"),
            "site.toml:5: port /dev/x is also claimed by 'a' (line 1): an LS5 stream holds its line, so one LS5 per "
            "port");
}

TEST(SiteConfig, AnUnreadableFileIsNamed) {
  auto site = load_site_config("/nonexistent/site.toml");
  ASSERT_FALSE(site.ok());
  EXPECT_EQ(site.error().code, Errc::io);
  EXPECT_EQ(site.error().message, "cannot read site file /nonexistent/site.toml");
}

}  // namespace

namespace site_file_password {

using rangekit::Errc;
using rangekit::hub::load_site_config;

std::string write_site(const std::filesystem::path& dir, const std::string& text, mode_t mode) {
  const std::string path = (dir / "site.toml").string();
  std::ofstream(path) << text;
  EXPECT_EQ(::chmod(path.c_str(), mode), 0);
  return path;
}

const std::string with_password =
    "[mqtt]\nbroker = \"mqtt://10.0.0.5\"\nusername = \"plant\"\npassword = \"secret\"\n"
    "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"/dev/x\"\n";

// The broker password in a site file anyone on the host may read is no secret: refused,
// naming the line and the remedy.
TEST(SiteFilePassword, AnInlinePasswordInAFileOthersMayReadIsRefused) {
  const ls5_driver_test::TempDir dir;
  for (const mode_t mode : {0644, 0640, 0604}) {
    const std::string path = write_site(dir.path, with_password, mode);
    auto site = load_site_config(path);
    ASSERT_FALSE(site.ok()) << std::oct << mode << ": accepted";
    EXPECT_EQ(site.error().code, Errc::io);
    std::array<char, 8> octal{};
    std::snprintf(octal.data(), octal.size(), "%04o", static_cast<unsigned>(mode));
    EXPECT_EQ(site.error().message, path + ":4: [mqtt] password in a file group or others may read (mode " +
                                        octal.data() + "): chmod 600 " + path);
  }
}

TEST(SiteFilePassword, AnOwnerOnlyFileOrOneWithoutAPasswordIsTaken) {
  const ls5_driver_test::TempDir dir;
  auto owner_only = load_site_config(write_site(dir.path, with_password, 0600));
  ASSERT_TRUE(owner_only.ok()) << owner_only.error().message;
  EXPECT_EQ(owner_only->mqtt.password, "secret");
  EXPECT_EQ(owner_only->mqtt.password_line, 4u);
  auto no_password = load_site_config(
      write_site(dir.path, "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"/dev/x\"\n", 0644));
  EXPECT_TRUE(no_password.ok()) << no_password.error().message;
}

// A baud the family's line cannot be set to is refused, naming the ones it can (ULS §8 BR,
// LS5 table 9.2 parameter 04), where 300-921600 let 115201 through.
TEST(SiteConfig, ABaudTheFamilyCannotRunIsRefused) {
  EXPECT_EQ(refusal("[[sensor]]\nname = \"a\"\nfamily = \"uls\"\nport = \"/dev/ttyUSB0\"\nbaud = 115201\n"),
            "site.toml:5: baud 115201 is not a baud of the ULS (1200, 2400, 4800, 9600, 14400, 19200, 38400, 57600, "
            "115200, 230400)");
  const std::string ls5 =
      refusal("[[sensor]]\nname = \"b\"\nfamily = \"ls5\"\nport = \"/dev/ttyUSB1\"\nbaud = 12345\n");
  EXPECT_EQ(ls5.rfind("site.toml:5: baud 12345 is not a baud of the LS5 (", 0), 0U) << ls5;
}

// Every mistake in one run: here six, in two sensors, a shared port and a name used twice.
TEST(SiteConfig, EveryMistakeIsReportedInOneRun) {
  const std::string message = refusal(R"([[sensor]]
name = "a"
family = "uls"
port = "/dev/ttyUSB0"
baud = 12345
address = "zz"
max_speed = -1

[[sensor]]
name = "a"
family = "ls5"
port = "/dev/ttyUSB0"
format = "9X9"
)");
  const std::vector<std::string> expected{
      "site.toml:5: baud 12345 is not a baud of the ULS", "site.toml:6: address 'zz' is not a ULS unit address",
      "site.toml:7: max_speed must be above 0",           "site.toml:13: format '9X9' is not an LS5 byte format",
      "site.toml:9: sensor name 'a' is already used at",  "site.toml:9: port /dev/ttyUSB0 is also claimed by 'a'",
  };
  std::size_t at = 0;
  for (const std::string& line : expected) {
    const auto found = message.find(line, at);
    ASSERT_NE(found, std::string::npos) << "missing, or out of order: " << line << "\nin:\n" << message;
    at = found;
  }
  EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 5) << message;
}

// An LS5 has a network address (table 9.2 01) but no bus: alone on its port it is no RS-485 bus.
TEST(SiteConfig, AnAddressedLs5AloneIsNoBus) {
  const auto site = parse_ok("[[sensor]]\nname = \"b\"\nfamily = \"ls5\"\nport = \"/dev/ttyUSB1\"\naddress = 5\n");
  const auto groups = port_groups(site);
  ASSERT_EQ(groups.size(), 1U);
  EXPECT_FALSE(groups.front().bus());
  const auto bus = parse_ok("[[sensor]]\nname = \"u\"\nfamily = \"uls\"\nport = \"/dev/ttyUSB1\"\naddress = \"A\"\n");
  EXPECT_TRUE(port_groups(bus).front().bus());  // a ULS addressed is on a bus, even alone (§7)
}

}  // namespace site_file_password
