// The historian sinks on the HTTP face (docs/api.md): GET /api/sinks, their lines of GET
// /metrics and their part of GET /healthz, from what the service describes (ServerOptions::sinks).
// The sinks against a real historian: tests/sinks/serve_sink_test.cpp.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "rangekit/web/server.hpp"
#include "web/http_client.hpp"
#include "web/sink_views.hpp"

namespace {

using rangekit::web::SinkHealth;

// A service of no sensor (so /healthz is "ok" but for the sinks) whose sinks are `sinks`.
struct SinkService {
  std::unique_ptr<rangekit::hub::Hub> hub = rangekit::hub::Hub::start(rangekit::hub::SiteConfig{});
  std::unique_ptr<rangekit::web::Server> server;
  std::uint16_t port = 0;
  explicit SinkService(std::function<std::vector<SinkHealth>()> sinks) {
    rangekit::web::ServerOptions options;
    options.listen = "127.0.0.1:0";
    options.sinks = std::move(sinks);
    auto started = rangekit::web::Server::start(*hub, options);
    EXPECT_TRUE(started.ok()) << (started.ok() ? "" : started.error().message);
    if (started) server = std::move(*started);
    if (server) port = server->local_endpoint().port;
  }
  nlohmann::json get_json(const std::string& target) const {
    return nlohmann::json::parse(web_test::http(port, "GET", target).body, nullptr, false);
  }
};

SinkHealth up_sink() { return {"influx", "http://127.0.0.1:8428/write", true, "", 5000, 12, 1480, 0, 0, 0, 0.04}; }

SinkHealth down_sink() {
  return {"postgres", "postgresql://u:***@db/plant", false, "connection refused", 10, 3000, 360000, 7, 2, 9, 31.5};
}

TEST(WebSinks, ApiSinksListsEachSinkWithItsCounts) {
  const SinkService service([] { return std::vector{up_sink(), down_sink()}; });
  const auto listed = service.get_json("/api/sinks");
  const auto expected = nlohmann::json::parse(R"([
    {"kind": "influx", "url": "http://127.0.0.1:8428/write", "up": true, "error": "", "written": 5000, "spooled": 12,
     "spool_bytes": 1480, "dropped": 0, "rejected": 0, "failures": 0, "oldest_age_s": 0.04},
    {"kind": "postgres", "url": "postgresql://u:***@db/plant", "up": false, "error": "connection refused",
     "written": 10, "spooled": 3000, "spool_bytes": 360000, "dropped": 7, "rejected": 2, "failures": 9,
     "oldest_age_s": 31.5}])");
  EXPECT_EQ(listed, expected);
  // A query key it does not read is refused, as on every other route.
  EXPECT_EQ(web_test::http(service.port, "GET", "/api/sinks?limit=1").status, 400);
  EXPECT_EQ(web_test::http(service.port, "POST", "/api/sinks", "{}").status, 405);
}

TEST(WebSinks, AServiceWithoutSinksAnswersAnEmptyListAndNoSinkMetric) {
  const SinkService service(nullptr);
  EXPECT_EQ(service.get_json("/api/sinks"), nlohmann::json::array());
  EXPECT_EQ(web_test::http(service.port, "GET", "/metrics").body.find("rangekit_sink_"), std::string::npos);
  const auto health = service.get_json("/healthz");
  EXPECT_EQ(health["status"], "ok") << health;
  EXPECT_FALSE(health.contains("sinks")) << health;
}

TEST(WebSinks, MetricsGiveEachSinkItsLinesLabelledByKindAndUrl) {
  SinkHealth odd = up_sink();
  odd.url = R"(http://h/write?tag="a\b")";  // escaped as the text format asks
  const SinkService service([&] { return std::vector{down_sink(), odd}; });
  const std::string text = web_test::http(service.port, "GET", "/metrics").body;
  const std::string down = R"({kind="postgres",url="postgresql://u:***@db/plant"} )";
  for (const std::string& line : std::vector<std::string>{
           "# TYPE rangekit_sink_up gauge", "rangekit_sink_up" + down + "0",
           "# TYPE rangekit_sink_rows_written_total counter", "rangekit_sink_rows_written_total" + down + "10",
           "rangekit_sink_rows_spooled" + down + "3000", "rangekit_sink_spool_bytes" + down + "360000",
           "rangekit_sink_oldest_spooled_age_seconds" + down + "31.500",
           "rangekit_sink_rows_dropped_total" + down + "7", "rangekit_sink_rows_rejected_total" + down + "2",
           "rangekit_sink_write_failures_total" + down + "9",
           R"(rangekit_sink_up{kind="influx",url="http://h/write?tag=\"a\\b\""} 1)"}) {
    EXPECT_NE(text.find("\n" + line + "\n"), std::string::npos) << line << "\nin\n" << text;
  }
}

TEST(WebSinks, HealthIsDegradedWhileASinkIsDownAndNotBeforeItsFirstWrite) {
  std::mutex mutex;  // the list is read on the server's event loop
  std::vector<SinkHealth> sinks{up_sink()};
  const auto set = [&](std::vector<SinkHealth> now) {
    const std::lock_guard lock(mutex);
    sinks = std::move(now);
  };
  const SinkService service([&] {
    const std::lock_guard lock(mutex);
    return sinks;
  });
  auto health = service.get_json("/healthz");
  EXPECT_EQ(health["status"], "ok") << health;
  ASSERT_EQ(health["sinks"].size(), 1U) << health;
  EXPECT_EQ(health["sinks"][0]["url"], "http://127.0.0.1:8428/write");

  SinkHealth unwritten = up_sink();  // no reading to send yet: no write, and none failed
  unwritten.up = false;
  unwritten.written = 0;
  set({unwritten});
  EXPECT_EQ(service.get_json("/healthz")["status"], "ok");
  set({up_sink(), down_sink()});
  health = service.get_json("/healthz");
  EXPECT_EQ(health["status"], "degraded") << health;
  EXPECT_EQ(health["sinks"][1]["error"], "connection refused") << health;
}

TEST(WebSinks, ASinkIsDownOnceAWriteFailed) {
  SinkHealth sink = up_sink();
  EXPECT_FALSE(rangekit::web::sink_down(sink));
  sink.up = false;
  EXPECT_FALSE(rangekit::web::sink_down(sink));  // not written yet
  sink.error = "HTTP 503";
  EXPECT_TRUE(rangekit::web::sink_down(sink));
}

}  // namespace
