// `rangekit serve` with a [[sink]]: --check describes it, and a run of the site's emulators
// into a real VictoriaMetrics says the sink at start and its counts at the end, and what it
// counts as written is in VictoriaMetrics; GET /api/sinks, /metrics and /healthz show it.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "hub/site_fixture.hpp"
#include "sinks/victoria_metrics.hpp"
#include "web/http_client.hpp"

namespace {

TEST(ServeSink, StartsOnePerSinkTableAndSaysItsCounts) {
  sinks_test::VictoriaMetrics vm;
  ASSERT_GT(vm.pid, 0);
  hub_test::Site site;
  const auto path = site.temp.path / "site.toml";
  std::ofstream(path) << "[service]\nlisten = \"127.0.0.1:0\"\n"
                      << hub_test::site_text(site.temp.path) << "[[sink]]\nkind = \"influx\"\nurl = \""
                      << vm.write_url() << "\"\nsensors = [\"belt\", \"silo\"]\n";
  auto check = ls5_driver_test::run_cli(site.temp.path, {"serve", "--check", path.string()});
  EXPECT_EQ(check.exit_code, 0) << check.err;
  EXPECT_NE(check.out.find("sink " + vm.write_url() + " (influx): belt, silo, every reading"), std::string::npos)
      << check.out;

  auto run = ls5_driver_test::run_cli(site.temp.path, {"serve", "--config", path.string(), "--duration", "4"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("rangekit serve: sink " + vm.write_url() + " (influx): 2 sensors, spool " +
                         (site.temp.path / "spool").string()),
            std::string::npos)
      << run.out;
  std::smatch counts;
  const std::regex summary("sink " + vm.write_url() + ": written ([0-9]+), spooled ([0-9]+), dropped 0");
  ASSERT_TRUE(std::regex_search(run.out, counts, summary)) << run.out;
  const auto written = std::stoull(counts[1]);
  EXPECT_GT(written, 0u);
  // Only the sensors named, each sequence complete, as many as the sink says it wrote.
  std::string problem;
  EXPECT_EQ(sinks_test::settled_total(vm, static_cast<long long>(written), problem), static_cast<long long>(written))
      << problem;
  for (const auto& [sensor, values] : vm.sequences()) EXPECT_TRUE(sensor == "belt" || sensor == "silo") << sensor;
}

// Reads the service's stdout up to its "API on http://127.0.0.1:PORT/" line; the port, 0 if none.
std::uint16_t api_port(ls5_driver_test::Child& service, std::string& said) {
  for (std::string line = service.read_line(); !line.empty(); line = service.read_line()) {
    said += line;
    const auto at = line.find("API on http://127.0.0.1:");
    if (at != std::string::npos) return static_cast<std::uint16_t>(std::stoi(line.substr(at + 24)));
  }
  return 0;
}

// GET /api/sinks until `wanted` holds of its one sink, or 30 s; that sink, null if never.
template <class Wanted>
nlohmann::json sink_once(std::uint16_t port, Wanted wanted) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  nlohmann::json sink;
  while (std::chrono::steady_clock::now() < deadline) {
    const auto listed = nlohmann::json::parse(web_test::http(port, "GET", "/api/sinks").body, nullptr, false);
    if (listed.is_array() && listed.size() == 1 && wanted(listed[0])) return listed[0];
    ::poll(nullptr, 0, 100);  // between two reads of the API, not a synchronisation
  }
  return sink;
}

// One line of /metrics: `NAME{kind="influx",url="URL"} VALUE`; the value, or -1 when absent.
double metric(const std::string& text, const std::string& name, const std::string& url) {
  const std::string head = name + "{kind=\"influx\",url=\"" + url + "\"} ";
  const auto at = text.find("\n" + head);
  return at == std::string::npos ? -1 : std::stod(text.substr(at + 1 + head.size()));
}

// The sink of --sink, up while VictoriaMetrics takes the rows and down with rows waiting once it
// is stopped, as GET /api/sinks, /metrics and /healthz show it; its password nowhere.
TEST(ServeSink, TheApiAndMetricsShowTheSinkUpThenDownWithRowsWaiting) {
  sinks_test::VictoriaMetrics vm;
  ASSERT_GT(vm.pid, 0);
  hub_test::Site site;
  const auto path = site.temp.path / "site.toml";
  std::ofstream(path) << "[service]\nlisten = \"127.0.0.1:0\"\n" << hub_test::site_text(site.temp.path);
  // VictoriaMetrics takes InfluxDB 1.x's query keys (db becomes a label, p is not looked at).
  const std::string shown = vm.write_url() + "?db=plant&p=***";
  ls5_driver_test::Child service({"serve", "--config", path.string(), "--sink",
                                  "influx+" + vm.write_url() + "?db=plant&p=secret", "--duration", "300"});
  std::string said;
  const std::uint16_t port = api_port(service, said);
  ASSERT_NE(port, 0) << said;
  EXPECT_NE(said.find("rangekit serve: sink " + shown + " (influx): every sensor, spool "), std::string::npos) << said;

  const auto up = sink_once(port, [](const nlohmann::json& sink) { return sink.value("written", 0) > 0; });
  ASSERT_TRUE(up.is_object()) << "no row written within 30 s";
  std::vector<std::string> keys;
  for (const auto& [key, value] : up.items()) keys.push_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{"dropped", "error", "failures", "kind", "oldest_age_s", "rejected",
                                            "spool_bytes", "spooled", "up", "url", "written"}));
  EXPECT_EQ(up["kind"], "influx");
  EXPECT_EQ(up["url"], shown);
  EXPECT_EQ(up["up"], true);
  EXPECT_EQ(up["error"], "");
  EXPECT_EQ(up["dropped"], 0);
  EXPECT_EQ(up["rejected"], 0);
  EXPECT_TRUE(up["oldest_age_s"].is_number());
  auto metrics = web_test::http(port, "GET", "/metrics").body;
  EXPECT_EQ(metric(metrics, "rangekit_sink_up", shown), 1) << metrics;
  EXPECT_GT(metric(metrics, "rangekit_sink_rows_written_total", shown), 0) << metrics;
  EXPECT_GE(metric(metrics, "rangekit_sink_rows_spooled", shown), 0) << metrics;
  EXPECT_EQ(metric(metrics, "rangekit_sink_rows_dropped_total", shown), 0) << metrics;
  EXPECT_NE(metrics.find("# TYPE rangekit_sink_rows_written_total counter\n"), std::string::npos);
  auto health = nlohmann::json::parse(web_test::http(port, "GET", "/healthz").body, nullptr, false);
  ASSERT_TRUE(health.contains("sinks")) << health;
  EXPECT_EQ(health["sinks"][0]["up"], true) << health;

  vm.stop();
  const auto down = sink_once(port, [](const nlohmann::json& sink) {
    return !sink.value("up", true) && sink.value("spooled", 0) > 0 && sink.value("oldest_age_s", 0.0) > 0.5;
  });
  ASSERT_TRUE(down.is_object()) << "the sink did not turn down with rows waiting within 30 s";
  EXPECT_NE(down["error"], "");
  EXPECT_GT(down["failures"], 0);
  EXPECT_GT(down["spool_bytes"], down["spooled"]);  // each row's text and more
  metrics = web_test::http(port, "GET", "/metrics").body;
  EXPECT_EQ(metric(metrics, "rangekit_sink_up", shown), 0) << metrics;
  EXPECT_GT(metric(metrics, "rangekit_sink_rows_spooled", shown), 0) << metrics;
  EXPECT_GT(metric(metrics, "rangekit_sink_spool_bytes", shown), 0) << metrics;
  EXPECT_GT(metric(metrics, "rangekit_sink_oldest_spooled_age_seconds", shown), 0.5) << metrics;
  EXPECT_GT(metric(metrics, "rangekit_sink_write_failures_total", shown), 0) << metrics;
  health = nlohmann::json::parse(web_test::http(port, "GET", "/healthz").body, nullptr, false);
  EXPECT_EQ(health["status"], "degraded") << health;
  EXPECT_EQ(health["sinks"][0]["up"], false) << health;
  const std::string api = web_test::http(port, "GET", "/api/sinks").body;
  for (const auto& served : {api, metrics, health.dump()})
    EXPECT_EQ(served.find("secret"), std::string::npos) << served;

  service.terminate();
  for (std::string line = service.read_line(); !line.empty(); line = service.read_line()) said += line;
  EXPECT_NE(said.find("sink " + shown + ": written "), std::string::npos) << said;
  EXPECT_NE(said.find("sink " + shown + ": down ("), std::string::npos) << said;
  // The spool's file is named after the URL: its folder alone is shown.
  EXPECT_EQ(said.find("secret"), std::string::npos) << said;
}

}  // namespace
