// `rangekit serve --sink URL` (docs/sinks.md): the URL forms it takes, the kind each makes, the
// refusal of the others, and a sink URL's password never printed (hub/sink_url.hpp).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "cli/commands.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/hub/sink_url.hpp"

namespace {

using rangekit::hub::parse_sink_option;
using rangekit::hub::redacted_text;
using rangekit::hub::redacted_url;

TEST(SinkUrl, APasswordIsReplacedWhereverTheUrlCarriesOne) {
  EXPECT_EQ(redacted_url("postgresql://u:secret@h/db"), "postgresql://u:***@h/db");
  EXPECT_EQ(redacted_url("postgres://u:secret@h:5432/db?sslmode=require"),
            "postgres://u:***@h:5432/db?sslmode=require");
  // libpq's and InfluxDB 1.x's query keys, and a token.
  EXPECT_EQ(redacted_url("postgresql://h/db?user=u&password=secret&sslmode=require"),
            "postgresql://h/db?user=u&password=***&sslmode=require");
  EXPECT_EQ(redacted_url("http://h:8086/write?db=plant&u=me&p=secret"), "http://h:8086/write?db=plant&u=me&p=***");
  EXPECT_EQ(redacted_url("http://h/api/v2/write?Token=secret"), "http://h/api/v2/write?Token=***");
  EXPECT_EQ(redacted_url("postgresql://u:secret@h/db?password=other"), "postgresql://u:***@h/db?password=***");
  // Unescaped '/', '?', '@' and '#' in a password: hidden all the same.
  EXPECT_EQ(redacted_url("postgresql://u:se/c?r@t#@h/db"), "postgresql://u:***@h/db");
  EXPECT_EQ(redacted_url("postgresql://h/db?password=se#cr&et"), "postgresql://h/db?password=***&et");
}

TEST(SinkUrl, AUrlWithoutAPasswordIsShownAsGiven) {
  for (const char* url : {"http://127.0.0.1:8428/write", "postgresql://u@h:5432/db", "postgresql://h/db?user=u",
                          "http://h/write?db=p&precision=ns", "postgresql://", "not a url"}) {
    EXPECT_EQ(redacted_url(url), url);
  }
}

TEST(SinkUrl, AMessageQuotingAUrlIsShownWithoutItsPassword) {
  EXPECT_EQ(redacted_text("url 'http://u:secret@h/write': no credentials in the URL"),
            "url 'http://u:***@h/write': no credentials in the URL");
  EXPECT_EQ(redacted_text("sink postgresql://u:a@h/db: down (refused)\nsink postgres://v:b@g/db: up"),
            "sink postgresql://u:***@h/db: down (refused)\nsink postgres://v:***@g/db: up");
  EXPECT_EQ(redacted_text("sink http://h/write?p=secret: down, 'http://h/write?token=abc', (http://h/w?p=x)."),
            "sink http://h/write?p=***: down, 'http://h/write?token=***', (http://h/w?p=***).");
  EXPECT_EQ(redacted_text("HTTP 503"), "HTTP 503");
}

TEST(SinkOption, EachAcceptedFormMakesItsKind) {
  auto postgres = parse_sink_option("postgresql://u:secret@h/db");
  ASSERT_TRUE(postgres.ok());
  EXPECT_EQ(postgres->kind, "postgres");
  EXPECT_EQ(postgres->url, "postgresql://u:secret@h/db");  // the sink gets it whole
  auto short_form = parse_sink_option("postgres://h/db");
  ASSERT_TRUE(short_form.ok());
  EXPECT_EQ(short_form->kind, "postgres");
  EXPECT_EQ(short_form->url, "postgres://h/db");
  auto influx = parse_sink_option("influx+http://127.0.0.1:8428/write");
  ASSERT_TRUE(influx.ok());
  EXPECT_EQ(influx->kind, "influx");
  EXPECT_EQ(influx->url, "http://127.0.0.1:8428/write");
  auto https = parse_sink_option("INFLUX+HTTPS://db.example:8086/api/v2/write?org=o&bucket=b");
  ASSERT_TRUE(https.ok());
  EXPECT_EQ(https->kind, "influx");
  EXPECT_EQ(https->url, "https://db.example:8086/api/v2/write?org=o&bucket=b");
  // A [[sink]] table's defaults: every sensor, every reading.
  const rangekit::hub::SinkConfig defaults;
  EXPECT_TRUE(influx->sensors.empty());
  EXPECT_EQ(influx->max_rate_hz, defaults.max_rate_hz);
  EXPECT_EQ(influx->spool_max_mb, defaults.spool_max_mb);
  EXPECT_EQ(influx->drain_rate, defaults.drain_rate);
}

TEST(SinkOption, AnyOtherFormIsRefusedNamingTheAcceptedOnesWithoutThePassword) {
  for (const char* url : {"http://127.0.0.1:8428/write", "mysql://u:secret@h/db", "influx://h/write", "postgresql:/h",
                          "", "127.0.0.1:8428"}) {
    auto refused = parse_sink_option(url);
    ASSERT_FALSE(refused.ok()) << url;
    const std::string& message = refused.error().message;
    EXPECT_NE(message.find("postgresql://"), std::string::npos) << message;
    EXPECT_NE(message.find("influx+http://"), std::string::npos) << message;
    EXPECT_NE(message.find("influx+https://"), std::string::npos) << message;
    EXPECT_EQ(message.find("secret"), std::string::npos) << message;
  }
}

// The service: a refused --sink is bad input and starts nothing; a postgres sink starts; the
// password shows nowhere.
TEST(SinkOption, TheServiceRefusesABadSinkAndNeverPrintsAPassword) {
  const ls5_driver_test::TempDir dir;
  const auto site = (dir.path / "site.toml").string();
  std::ofstream(site) << "[service]\nlisten = \"127.0.0.1:0\"\n[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \""
                      << (dir.path / "absent").string() << "\"\n";
  auto run = ls5_driver_test::run_cli(dir.path, {"serve", "--config", site, "--sink", "mysql://u:secret@h/db"});
  EXPECT_EQ(run.exit_code, rangekit::cli::exit_bad_input);
  EXPECT_NE(run.err.find("--sink 'mysql://u:***@h/db': give postgresql://"), std::string::npos) << run.err;
  EXPECT_EQ(run.out.find("API on"), std::string::npos) << run.out;
  run = ls5_driver_test::run_cli(dir.path, {"serve", "--demo", "--sink", "http://127.0.0.1:9/write"});
  EXPECT_EQ(run.exit_code, rangekit::cli::exit_bad_input);
  EXPECT_EQ(run.out.find("emulators"), std::string::npos) << "refused before the demo starts: " << run.out;
  run = ls5_driver_test::run_cli(dir.path, {"serve", "--config", site, "--sink", "influx+http://u:secret@h/write"});
  EXPECT_EQ(run.exit_code, rangekit::cli::exit_bad_input);
  EXPECT_NE(run.err.find("'http://u:***@h/write': no credentials in the URL"), std::string::npos) << run.err;

  run = ls5_driver_test::run_cli(dir.path, {"serve", "--check", site, "--sink", "postgresql://u:secret@h/db", "--sink",
                                            "influx+http://127.0.0.1:8428/write?db=plant&p=secret"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("sink postgresql://u:***@h/db (postgres): every sensor, every reading"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("sink http://127.0.0.1:8428/write?db=plant&p=*** (influx): every sensor"), std::string::npos)
      << run.out;

  // The kind is built: the sink starts though nothing listens there, and says so at the end.
  run = ls5_driver_test::run_cli(
      dir.path, {"serve", "--config", site, "--sink", "postgresql://u:secret@127.0.0.1:9/db", "--duration", "2"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("rangekit serve: sink postgresql://u:***@127.0.0.1:9/db (postgres): every sensor"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("sink postgresql://u:***@127.0.0.1:9/db: written 0"), std::string::npos) << run.out;
  for (const auto& output : {run.out, run.err}) EXPECT_EQ(output.find("secret"), std::string::npos) << output;
}

}  // namespace
