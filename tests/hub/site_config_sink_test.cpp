// [[sink]] tables of site.toml: what `rangekit serve --config` and `--check` accept and
// refuse (docs/sinks.md), each refusal at its FILE:LINE.
#include <gtest/gtest.h>

#include <string>

#include "rangekit/hub/site_config.hpp"

namespace site_file_sinks {

using rangekit::Errc;
using namespace rangekit::hub;

const std::string sensors =
    "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"/dev/ttyUSB0\"\n"    // lines 1-4
    "[[sensor]]\nname = \"bay-A\"\nfamily = \"uls\"\nport = \"/dev/ttyUSB1\"\n";  // lines 5-8

std::string refusal(const std::string& text) {
  auto site = parse_site_config(text, "site.toml");
  EXPECT_FALSE(site.ok()) << "accepted:\n" << text;
  return site.ok() ? "" : site.error().message;
}

TEST(SiteConfigSink, ReadsEveryKey) {
  auto site = parse_site_config(sensors +
                                    "[[sink]]\n"                               // 9
                                    "kind = \"influx\"\n"                      // 10
                                    "url = \"http://127.0.0.1:8428/write\"\n"  // 11
                                    "sensors = [\"belt\"]\n"                   // 12
                                    "max_rate_hz = 50\n"                       // 13
                                    "spool_max_mb = 64\n"                      // 14
                                    "drain_rate = 5000\n"                      // 15
                                    "[[sink]]\nkind = \"influx\"\nurl = \"http://historian.lan/write?db=plant\"\n",
                                "site.toml");
  ASSERT_TRUE(site.ok()) << site.error().message;
  ASSERT_EQ(site->sinks.size(), 2u);
  const SinkConfig& first = site->sinks[0];
  EXPECT_EQ(first.kind, "influx");
  EXPECT_EQ(first.url, "http://127.0.0.1:8428/write");
  EXPECT_EQ(first.sensors, std::vector<std::string>{"belt"});
  EXPECT_EQ(first.max_rate_hz, 50);
  EXPECT_EQ(first.spool_max_mb, 64u);
  EXPECT_EQ(first.drain_rate, 5000u);
  EXPECT_EQ(first.line, 9u);
  const SinkConfig& second = site->sinks[1];  // the defaults
  EXPECT_TRUE(second.sensors.empty());
  EXPECT_EQ(second.max_rate_hz, 0);
  EXPECT_EQ(second.spool_max_mb, 1024u);
  EXPECT_EQ(second.drain_rate, 20000u);
}

TEST(SiteConfigSink, ASiteWithoutSinksHasNone) {
  auto site = parse_site_config(sensors, "site.toml");
  ASSERT_TRUE(site.ok());
  EXPECT_TRUE(site->sinks.empty());
}

TEST(SiteConfigSink, RefusesAKindNotBuiltListingTheAccepted) {
  EXPECT_EQ(refusal(sensors + "[[sink]]\nkind = \"kafka\"\nurl = \"http://127.0.0.1:8428/write\"\n"),
            "site.toml:10: kind 'kafka' is not a sink kind (accepted: influx, postgres)");
}

TEST(SiteConfigSink, ReadsAPostgresSink) {
  auto site = parse_site_config(sensors +
                                    "[[sink]]\n"                                              // 9
                                    "kind = \"postgres\"\n"                                   // 10
                                    "url = \"postgresql://rangekit@127.0.0.1:5432/plant\"\n"  // 11
                                    "table = \"line_3\"\n"                                    // 12
                                    "password_file = \"secrets/pg\"\n"                        // 13
                                    "[[sink]]\nkind = \"postgres\"\nurl = \"postgres://db.lan/plant\"\n"
                                    "password_env = \"PLANT_DB_PASSWORD\"\n",
                                "/etc/rangekit/site.toml");
  ASSERT_TRUE(site.ok()) << site.error().message;
  ASSERT_EQ(site->sinks.size(), 2u);
  EXPECT_EQ(site->sinks[0].kind, "postgres");
  EXPECT_EQ(site->sinks[0].table, "line_3");
  EXPECT_EQ(site->sinks[0].password_file, "/etc/rangekit/secrets/pg") << "beside the site file";
  EXPECT_TRUE(site->sinks[0].password_env.empty());
  EXPECT_EQ(site->sinks[1].table, "readings");
  EXPECT_EQ(site->sinks[1].password_env, "PLANT_DB_PASSWORD");
  auto absolute = parse_site_config(sensors +
                                        "[[sink]]\nkind = \"postgres\"\nurl = \"postgres://db/plant\"\n"
                                        "password_file = \"/run/secrets/pg\"\n",
                                    "site.toml");
  ASSERT_TRUE(absolute.ok()) << absolute.error().message;
  EXPECT_EQ(absolute->sinks[0].password_file, "/run/secrets/pg");
}

TEST(SiteConfigSink, RefusesPostgresSettingsThatCannotWork) {
  const std::string head = sensors + "[[sink]]\nkind = \"postgres\"\nurl = \"postgresql://u@h/plant\"\n";
  EXPECT_EQ(
      refusal(head + "table = \"readings; DROP TABLE x\"\n"),
      "site.toml:12: table 'readings; DROP TABLE x': a letter or '_', then letters, digits or '_', at most 63 (an "
      "SQL identifier)");
  EXPECT_EQ(refusal(head + "table = \"\"\n").substr(0, 23), "site.toml:12: table '':");
  EXPECT_EQ(refusal(head + "password_file = \"a\"\npassword_env = \"B\"\n"),
            "site.toml:9: [[sink]]: password_file or password_env, not both");
  EXPECT_EQ(refusal(head + "password_env = \"\"\n"), "site.toml:12: password_env is empty");
  EXPECT_EQ(refusal(sensors + "[[sink]]\nkind = \"influx\"\nurl = \"http://h:1/w\"\ntable = \"readings\"\n"),
            "site.toml:12: table, password_file and password_env are for kind postgres");
  const auto url = [](const std::string& text) {
    return refusal(sensors + "[[sink]]\nkind = \"postgres\"\nurl = \"" + text + "\"\n");
  };
  EXPECT_EQ(url("http://127.0.0.1:5432/plant"),
            "site.toml:11: url 'http://127.0.0.1:5432/plant': give postgresql://USER@HOST[:PORT]/DATABASE");
  EXPECT_EQ(url("postgresql://u@:5432/plant"), "site.toml:11: url 'postgresql://u@:5432/plant': no host name in it");
  // The message never shows the password.
  EXPECT_EQ(url("postgresql://u:hunter2@h:0/plant"),
            "site.toml:11: url 'postgresql://u:***@h:0/plant': the port '0' is not 1-65535");
  // An http URL for an influx sink only.
  EXPECT_EQ(refusal(sensors + "[[sink]]\nkind = \"influx\"\nurl = \"postgresql://u@h/plant\"\n"),
            "site.toml:11: url 'postgresql://u@h/plant': give http://HOST:PORT/PATH (https is not built)");
}

TEST(SiteConfigSink, AnSqlIdentifierIsALetterOrUnderscoreThenWordCharacters) {
  EXPECT_TRUE(valid_sql_identifier("readings"));
  EXPECT_TRUE(valid_sql_identifier("_line3"));
  EXPECT_TRUE(valid_sql_identifier("Plant_Readings"));
  EXPECT_TRUE(valid_sql_identifier(std::string(63, 'a')));
  EXPECT_FALSE(valid_sql_identifier(std::string(64, 'a'))) << "NAMEDATALEN - 1";
  EXPECT_FALSE(valid_sql_identifier(""));
  EXPECT_FALSE(valid_sql_identifier("3rd_line"));
  EXPECT_FALSE(valid_sql_identifier("plant.readings"));
  EXPECT_FALSE(valid_sql_identifier("read ings"));
  EXPECT_FALSE(valid_sql_identifier("read\"ings"));
  EXPECT_FALSE(valid_sql_identifier("r\xc3\xa9sultats")) << "ASCII only";
}

TEST(SiteConfigSink, RefusesUrlsThatCannotWork) {
  const auto url = [](const std::string& text) {
    return refusal(sensors + "[[sink]]\nkind = \"influx\"\nurl = \"" + text + "\"\n");
  };
  EXPECT_EQ(url("https://127.0.0.1:8086/write"),
            "site.toml:11: url 'https://127.0.0.1:8086/write': give http://HOST:PORT/PATH (https is not built)");
  EXPECT_EQ(url("http://127.0.0.1:0/write"),
            "site.toml:11: url 'http://127.0.0.1:0/write': the port '0' is not 1-65535");
  EXPECT_EQ(url("http://127.0.0.1:99999/write"),
            "site.toml:11: url 'http://127.0.0.1:99999/write': the port '99999' is not 1-65535");
  EXPECT_EQ(url("http://:8428/write"), "site.toml:11: url 'http://:8428/write': no host name in it");
  EXPECT_EQ(url("http://user:secret@host:8086/write"),
            "site.toml:11: url 'http://user:secret@host:8086/write': no credentials in the URL");
}

TEST(SiteConfigSink, RefusesAnUnknownSensorAtItsLine) {
  EXPECT_EQ(
      refusal(sensors + "[[sink]]\nkind = \"influx\"\nurl = \"http://127.0.0.1:8428/write\"\nsensors = [\n  \"belt\",\n"
                        "  \"bay-Z\",\n]\n"),
      "site.toml:14: sensors: 'bay-Z' is no sensor of this site");
}

TEST(SiteConfigSink, RefusesUnknownKeysMissingKeysAndBadNumbers) {
  EXPECT_EQ(refusal(sensors + "[[sink]]\nkind = \"influx\"\nurl = \"http://h:1/w\"\ntable = \"readings\"\n"),
            "site.toml:12: table, password_file and password_env are for kind postgres");
  EXPECT_EQ(refusal(sensors + "[[sink]]\nkind = \"influx\"\nurl = \"http://h:1/w\"\ntoken = \"x\"\n"),
            "site.toml:12: unknown key 'token' in [[sink]] (allowed: kind, url, sensors, max_rate_hz, spool_max_mb, "
            "drain_rate, table, password_file, password_env)");
  EXPECT_EQ(refusal(sensors + "[[sink]]\nurl = \"http://h:1/w\"\n"),
            "site.toml:9: [[sink]] needs a kind (influx, postgres)");
  EXPECT_EQ(refusal(sensors + "[[sink]]\nkind = \"influx\"\n"), "site.toml:9: [[sink]] needs a url");
  EXPECT_EQ(refusal(sensors + "[[sink]]\nkind = \"influx\"\nurl = \"http://h:1/w\"\nspool_max_mb = 0\n"),
            "site.toml:12: spool_max_mb = 0: 1 to 1048576 MB (1 TB)");
  EXPECT_EQ(refusal(sensors + "[[sink]]\nkind = \"influx\"\nurl = \"http://h:1/w\"\nmax_rate_hz = -1\n"),
            "site.toml:12: max_rate_hz = -1.000000: 0 (every sample) or up to 10000 a second");
  auto code = parse_site_config(
      sensors + "[[sink]]\nkind = \"influx\"\nurl = \"http://h:1/w\"\ndrain_rate = \"fast\"\n", "site.toml");
  ASSERT_FALSE(code.ok());
  EXPECT_EQ(code.error().code, Errc::invalid_frame);
  EXPECT_EQ(code.error().message, "site.toml:12: drain_rate must be an integer");
}

}  // namespace site_file_sinks
