// The HTTP API end to end (docs/api.md): the hub serving an LS5, a
// ULS alone and a bus of four ULS units on ptys, the server on a loopback port, and
// every kind of bad request answered with a 4xx JSON error that names the field.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <latch>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "hub/site_fixture.hpp"
#include "rangekit/sim/control_socket.hpp"
#include "rangekit/web/server.hpp"
#include "web/http_client.hpp"

namespace {

using namespace rangekit;
using web_test::http;
using web_test::Reply;

struct ApiService {
  hub_test::Site site;
  std::unique_ptr<hub::Hub> hub = hub::Hub::start(site.config);
  hub::CaptureManager captures{*hub, (site.temp.path / "captures").string()};
  std::unique_ptr<web::Server> server;
  std::uint16_t port = 0;
  explicit ApiService(web::ServerOptions options = {}) {
    options.listen = "127.0.0.1:0";
    options.captures = &captures;
    auto started = web::Server::start(*hub, options);
    EXPECT_TRUE(started.ok()) << (started.ok() ? "" : started.error().message);
    if (started) server = std::move(*started);
    if (server) port = server->local_endpoint().port;
  }
  // Waits (bounded) until every sensor has been heard, through the API itself.
  bool all_live() {
    web_test::EventReader events(port, "/api/events");
    std::set<std::string> heard;
    return events.read_until([&](const web_test::Event& event) {
      if (event.type == "sample") heard.insert(nlohmann::json::parse(event.data)["sensor"].get<std::string>());
      return heard.size() == 6;
    });
  }
};

nlohmann::json json_of(const Reply& reply) { return nlohmann::json::parse(reply.body, nullptr, false); }

std::string error_field(const Reply& reply) {
  const auto json = json_of(reply);
  return json.contains("error") ? json["error"].value("field", "") : "<no error>";
}

TEST(WebApi, ListsEverySensorWithIdentityStatusAndHealth) {
  ApiService service;
  ASSERT_TRUE(service.all_live());
  const Reply list = http(service.port, "GET", "/api/sensors");
  ASSERT_EQ(list.status, 200) << list.body;
  EXPECT_EQ(list.headers.at("content-type"), "application/json");
  const auto sensors = json_of(list)["sensors"];
  ASSERT_EQ(sensors.size(), 6u);
  EXPECT_EQ(sensors[0]["name"], "belt");
  EXPECT_EQ(sensors[0]["identity"]["version"], "LS5.12.0");  // `sim ls5` default firmware
  EXPECT_EQ(sensors[0]["identity"]["serial"], 157);
  // L68: the names `ls5 info --json` prints, the unit last (docs/cli.md "One vocabulary"); the
  // `sim ls5` default model 8.1234/40.001.
  EXPECT_EQ(sensors[0]["identity"]["lower-boundary-mm"], 8.1234) << sensors[0]["identity"].dump();
  EXPECT_EQ(sensors[0]["identity"]["range-mm"], 40.001) << sensors[0]["identity"].dump();
  EXPECT_FALSE(sensors[0]["identity"].contains("range")) << sensors[0]["identity"].dump();
  for (const auto& sensor : sensors) {
    EXPECT_TRUE(sensor["connected"].get<bool>()) << sensor["name"];
    EXPECT_GT(sensor["health"]["records"].get<int>(), 0) << sensor["name"];
    // Read when the sensor connected, before anyone asked for them.
    EXPECT_GT(sensor["settings"].size(), 10U) << sensor.dump();
  }
  EXPECT_EQ(sensors[0]["settings"]["median-points"], 5) << sensors[0]["settings"].dump();
  EXPECT_EQ(sensors[1]["settings"]["prf-hz"], nlohmann::json::parse("[2000,2000,2000]")) << sensors[1].dump();
  const Reply one = http(service.port, "GET", "/api/sensors/bay-C");
  ASSERT_EQ(one.status, 200);
  // One spelling in one object: the site file's "C" (§8 UA table) beside `identity`'s, the byte once.
  EXPECT_EQ(json_of(one)["identity"]["address"], "C");
  EXPECT_EQ(json_of(one)["address"], "C");
  EXPECT_EQ(json_of(one)["address_code"], 0x43);
  EXPECT_FALSE(sensors[1].contains("address")) << sensors[1].dump();  // alone on its port: none
  const Reply health = http(service.port, "GET", "/healthz");
  EXPECT_EQ(health.status, 200);
  EXPECT_EQ(json_of(health)["status"], "ok");
  const Reply metrics = http(service.port, "GET", "/metrics");
  EXPECT_EQ(metrics.status, 200);
  EXPECT_NE(metrics.body.find("rangekit_sensor_connected{sensor=\"bay-D\",family=\"uls\"} 1"), std::string::npos);
  EXPECT_NE(metrics.body.find("# TYPE rangekit_sensor_records_total counter"), std::string::npos);
}

TEST(WebApi, RecentSamplesComeFromTheRing) {
  ApiService service;
  ASSERT_TRUE(service.all_live());
  const Reply latest = http(service.port, "GET", "/api/sensors/belt/samples?limit=3");
  ASSERT_EQ(latest.status, 200) << latest.body;
  const auto items = json_of(latest)["items"];
  ASSERT_EQ(items.size(), 3u);
  EXPECT_EQ(items[0]["data"]["device"], "ls5");
  const auto first = items[0]["id"].get<std::uint64_t>();
  const Reply after =
      http(service.port, "GET", "/api/sensors/belt/samples?after=" + std::to_string(first) + "&limit=2");
  ASSERT_EQ(after.status, 200);
  EXPECT_EQ(json_of(after)["items"][0]["id"], items[1]["id"]);
  EXPECT_TRUE(json_of(after)["complete"].get<bool>());
}

// LS5 table 9.2 (L4): the median filter takes an odd number of points, 1-49. The PATCH reaches
// the sensor: its own control socket reports the value, and a refused one changes nothing.
TEST(WebApi, PatchIsCheckedByTheTableWrittenAndReadBack) {
  ApiService service;
  ASSERT_TRUE(service.all_live());
  Reply refused = http(service.port, "PATCH", "/api/sensors/belt/settings", R"({"median-points": 8})");
  EXPECT_EQ(refused.status, 400) << refused.body;
  EXPECT_EQ(error_field(refused), "median-points");
  EXPECT_NE(json_of(refused)["error"]["message"].get<std::string>().find("odd"), std::string::npos) << refused.body;
  EXPECT_EQ(json_of(refused)["error"]["code"], "out_of_range");

  const Reply changed = http(service.port, "PATCH", "/api/sensors/belt/settings", R"({"median-points": 7})");
  ASSERT_EQ(changed.status, 200) << changed.body;
  EXPECT_EQ(json_of(changed)["median-points"], 7);
  EXPECT_EQ(json_of(http(service.port, "GET", "/api/sensors/belt/settings"))["median-points"], 7);

  // A bus unit, by the names `rangekit uls get` prints (§8 Set Short Gate 0-1700 m).
  const Reply gate = http(service.port, "PATCH", "/api/sensors/bay-B/settings", R"({"short-gate-m": 12.5})");
  ASSERT_EQ(gate.status, 200) << gate.body;
  EXPECT_EQ(json_of(gate)["short-gate-m"], 12.5);
  const Reply too_far = http(service.port, "PATCH", "/api/sensors/bay-B/settings", R"({"short-gate-m": 2000})");
  EXPECT_EQ(too_far.status, 400) << too_far.body;
  EXPECT_EQ(error_field(too_far), "short-gate-m");
  EXPECT_NE(too_far.body.find("1700"), std::string::npos) << too_far.body;
}

// U119: the ranges the dashboard checks a field by before it sends anything
// ("every field shows the document's range and unit"), served from the command table the
// CLI uses. Expectations typed from §8: "Set/Get PRF ... 10 to 5000 Hz" (error 32 "Invalid
// PRF"), Short Gate 0-1700 m, Bin Size 0-8 (§2 "2.5 (13)"), Measurement Mode 1-3.
TEST(WebApi, SettingsSchemaGivesEachSettingsRangeUnitAndError) {
  ApiService service;
  const Reply reply = http(service.port, "GET", "/api/sensors/bay-C/settings/schema");
  ASSERT_EQ(reply.status, 200) << reply.body;
  const auto schema = json_of(reply);
  EXPECT_EQ(schema["family"], "uls");
  std::map<std::string, nlohmann::json> by_key;
  for (const auto& row : schema["settings"]) by_key[row["key"].get<std::string>()] = row;
  const auto& prf = by_key.at("prf-hz");
  EXPECT_EQ(prf["mnemonic"], "PF");
  EXPECT_EQ(prf["min"], 10);
  EXPECT_EQ(prf["max"], 5000);
  EXPECT_EQ(prf["unit"], "Hz");
  EXPECT_EQ(prf["error"], 32);
  EXPECT_EQ(prf["max_fields"], 3);
  const auto& gate = by_key.at("short-gate-m");
  EXPECT_EQ(gate["min"], 0);
  EXPECT_EQ(gate["max"], 1700);
  EXPECT_EQ(gate["unit"], "m");
  EXPECT_EQ(by_key.at("offset-m")["min"], -1700);
  EXPECT_EQ(by_key.at("bin-size")["values"][0]["name"], "1 inch");     // §8 BS "n = 0 = 1 inch"
  EXPECT_EQ(by_key.at("bin-size")["values"][0]["label"], "2.5 (13)");  // §2 "Bin Size (Range) 2.5 (13)"
  EXPECT_EQ(by_key.at("mode")["values"][0]["name"], "averaging");
  EXPECT_EQ(by_key.at("trip-timeout-s")["unit"], "s");
  EXPECT_FALSE(by_key.at("version")["writable"].get<bool>());
  // §10: "49 Pulse Per Output Must Be Greater Than Average Weight | PPO Must Be Greater Than Average Weight".
  bool error_49 = false;
  for (const auto& error : schema["errors"]) {
    if (error["number"] != 49) continue;
    error_49 = true;
    EXPECT_EQ(error["explanation"], "Pulse Per Output Must Be Greater Than Average Weight");
    EXPECT_EQ(error["display"], "PPO Must Be Greater Than Average Weight");
  }
  EXPECT_TRUE(error_49);
  EXPECT_EQ(http(service.port, "POST", "/api/sensors/bay-C/settings/schema").status, 405);
}

// The LS5 page's fields come from table 9.2 as the host catalog names them:
// "Measurement period (discrete - 0.1 ms, minimum value - 0.1 ms) ... 0001-FFFF"; "Number of
// points of the median filter, m (must be odd ...) 01, 03, 05, ..., 31"; "Latching ... 09 - the
// same for the value 08" (L6: from LS5.9.0); "Network address 01-FF" changes the link (L28).
// L73: the page's fields and checks come from this schema.
TEST(WebApi, Ls5SettingsSchemaFollowsTable92) {
  ApiService service;
  const Reply reply = http(service.port, "GET", "/api/sensors/belt/settings/schema");
  ASSERT_EQ(reply.status, 200) << reply.body;
  const auto schema = json_of(reply);
  EXPECT_EQ(schema["family"], "ls5");
  std::map<std::string, nlohmann::json> by_key;
  for (const auto& row : schema["settings"]) by_key[row["key"].get<std::string>()] = row;
  const auto& period = by_key.at("period-ms");
  EXPECT_DOUBLE_EQ(period["min"].get<double>(), 0.1);
  EXPECT_DOUBLE_EQ(period["max"].get<double>(), 6553.5);  // 0xFFFF x 0.1 ms
  EXPECT_DOUBLE_EQ(period["step"].get<double>(), 0.1);
  EXPECT_EQ(period["unit"], "ms");
  EXPECT_EQ(period["addresses"], nlohmann::json::array({"06", "07"}));
  const auto& median = by_key.at("median-points");
  EXPECT_EQ(median["min"], 1);
  EXPECT_EQ(median["max"], 49);  // L4: "31" is hex, h = 0...24 gives m up to 49
  EXPECT_EQ(median["step"], 2);
  EXPECT_EQ(by_key.at("analog-upper")["max"], 50000);  // §8.10 "only be in the range 0÷50000"
  const auto& latching = by_key.at("latching");
  EXPECT_EQ(latching["addresses"], nlohmann::json::array({"1F"}));
  ASSERT_EQ(latching["values"].size(), 10U);  // 00-09
  EXPECT_EQ(latching["values"][9]["byte"], "09");
  EXPECT_EQ(latching["values"][9]["since"], "LS5.9.0");
  EXPECT_TRUE(latching["values"][0]["since"].is_null());
  EXPECT_TRUE(by_key.at("udp-auto-stream")["ethernet_only"].get<bool>());  // table 9.2 note 5
  EXPECT_FALSE(by_key.at("network-address")["writable"].get<bool>());
  EXPECT_EQ(by_key.count("analog-lower-mm"), 0U);  // the page converts codes with the ID's range
}

TEST(WebApi, ActionsRunOnTheSensor) {
  ApiService service;
  ASSERT_TRUE(service.all_live());
  const Reply single = http(service.port, "POST", "/api/sensors/bay-A/actions/single");
  ASSERT_EQ(single.status, 200) << single.body;
  EXPECT_NE(json_of(single)["result"].get<std::string>().find(" m"), std::string::npos) << single.body;
  // The measurement as a value with its unit, and as the stream's line: nothing to parse.
  const auto reading = json_of(single)["reading"];
  EXPECT_EQ(reading["unit"], "m") << single.body;
  EXPECT_EQ(reading["quantity"], "distance") << single.body;
  EXPECT_EQ(reading["channel"], "distance_m") << single.body;
  EXPECT_NEAR(reading["value"].get<double>(), std::stod(json_of(single)["result"].get<std::string>()), 0.0005);
  EXPECT_EQ(json_of(single)["sample"]["device"], "uls") << single.body;
  const Reply stop = http(service.port, "POST", "/api/sensors/belt/actions/stop");
  ASSERT_EQ(stop.status, 200) << stop.body;
  EXPECT_FALSE(json_of(http(service.port, "GET", "/api/sensors/belt"))["streaming"].get<bool>());
  auto control = ControlClient::connect(service.site.ls5_control);
  ASSERT_TRUE(control.ok());
  auto outputs = control->request({{"cmd", "outputs"}});
  ASSERT_TRUE(outputs.ok());
  const auto& device = outputs->contains("devices") ? (*outputs)["devices"][0] : *outputs;
  EXPECT_EQ(device["streaming"], false);  // table 9.1 SB reached the sensor
  EXPECT_EQ(http(service.port, "POST", "/api/sensors/belt/actions/start").status, 200);
  // L75: table 9.1 "Latch the result" FX, then "Read the latched result" FR: the latched code is returned.
  const Reply latch = http(service.port, "POST", "/api/sensors/belt/actions/latch");
  ASSERT_EQ(latch.status, 200) << latch.body;
  EXPECT_NE(json_of(latch)["result"].get<std::string>().find("(code "), std::string::npos) << latch.body;
  const auto latched_code = json_of(latch)["sample"]["code"];
  EXPECT_NE(json_of(latch)["result"].get<std::string>().find("(code " + latched_code.dump() + ")"), std::string::npos)
      << latch.body;
  if (!json_of(latch)["reading"].is_null()) {
    EXPECT_EQ(json_of(latch)["reading"]["unit"], "mm") << latch.body;
  }
  const Reply latched = http(service.port, "POST", "/api/sensors/belt/actions/latch?argument=read");
  ASSERT_EQ(latched.status, 200) << latched.body;
  EXPECT_EQ(json_of(latched)["result"], json_of(latch)["result"]);  // FR alone reads the same latch
  // The ULS has a pointer (PT), the LS5 none: its actions are its family's.
  const Reply pointer = http(service.port, "POST", "/api/sensors/belt/actions/pointer", R"({"argument":"on"})");
  EXPECT_EQ(pointer.status, 400) << pointer.body;
  EXPECT_EQ(json_of(pointer)["error"]["code"], "unknown_action");
  EXPECT_EQ(json_of(pointer)["error"]["message"],
            "'pointer' is not an action of ls5 sensor 'belt' (start, stop, read, single, save, reset, latch)");
  const Reply no_argument = http(service.port, "POST", "/api/sensors/bay-A/actions/pointer");
  EXPECT_EQ(no_argument.status, 400) << no_argument.body;
  EXPECT_EQ(json_of(no_argument)["error"]["message"], "pointer needs an argument: on or off");
}

TEST(WebApi, EveryBadRequestGetsA4xxThatNamesTheProblem) {
  web::ServerOptions options;
  options.max_body_bytes = 1024;
  options.max_header_bytes = 2048;
  ApiService service(options);
  const std::uint16_t port = service.port;
  const auto expect = [&](const Reply& reply, int status, const std::string& code, const std::string& field = "") {
    EXPECT_EQ(reply.status, status) << reply.body;
    const auto json = json_of(reply);
    ASSERT_TRUE(json.contains("error")) << reply.body;
    EXPECT_EQ(json["error"]["code"], code) << reply.body;
    if (!field.empty()) {
      EXPECT_EQ(json["error"]["field"], field) << reply.body;
    }
  };
  expect(http(port, "GET", "/api/sensors/nope"), 404, "not_found");
  expect(http(port, "GET", "/api/nothing"), 404, "not_found");
  expect(http(port, "GET", "/api/sensors/bel%zzt"), 400, "bad_target");
  // A query key no route reads is refused, not ignored (the default limit would answer).
  const Reply typo = http(port, "GET", "/api/sensors/belt/samples?limt=5");
  expect(typo, 400, "unknown_parameter", "limt");
  EXPECT_EQ(json_of(typo)["error"]["message"],
            "'limt' is no query parameter of GET /api/sensors/{name}/samples; did you mean 'limit'? (it takes after, "
            "limit)");
  expect(http(port, "GET", "/api/sensors?verbose=1"), 400, "unknown_parameter", "verbose");
  EXPECT_EQ(http(port, "GET", "/api/sensors/belt/samples?limit=2").status, 200);
  const Reply wrong_method = http(port, "DELETE", "/api/sensors/belt");
  expect(wrong_method, 405, "method_not_allowed");
  EXPECT_EQ(wrong_method.headers.at("allow"), "GET");
  expect(http(port, "PATCH", "/api/sensors/belt/settings", "median-points=7"), 400, "bad_body");
  expect(http(port, "PATCH", "/api/sensors/belt/settings", "[1,2]"), 400, "bad_body");
  expect(http(port, "PATCH", "/api/sensors/belt/settings", R"({"median-points": {"a":1}})"), 400, "bad_body",
         "median-points");
  expect(http(port, "PATCH", "/api/sensors/belt/settings", R"({"no-such-setting": 1})"), 400, "unknown_parameter",
         "no-such-setting");
  expect(http(port, "PATCH", "/api/sensors/silo/settings", R"({"version": "x"})"), 400, "wrong_form", "version");
  // §8 BS: 4 is no bin size (code 4 is 16 inches); "4-inches" is.
  expect(http(port, "PATCH", "/api/sensors/silo/settings", R"({"bin-size": 4})"), 400, "out_of_range", "bin-size");
  expect(http(port, "PATCH", "/api/sensors/belt/settings", "{\"median-points\": \"" + std::string(2000, '1') + "\"}"),
         413, "body_too_large");
  expect(http(port, "GET", "/api/sensors", {}, {"X-Long: " + std::string(4000, 'a')}), 431, "headers_too_large");
  expect(http(port, "POST", "/api/sensors/belt/actions/explode"), 400, "unknown_action", "action");
  expect(http(port, "POST", "/api/sensors/silo/actions/pointer", R"({"argument": 1})"), 400, "bad_body", "argument");
  expect(http(port, "GET", "/api/sensors/belt/samples?limit=0"), 400, "out_of_range", "limit");
  expect(http(port, "GET", "/api/sensors/belt/samples?after=x"), 400, "out_of_range", "after");
  expect(http(port, "GET", "/api/events?max_rate=0"), 400, "out_of_range", "max_rate");
  // DNS rebinding: a name that resolved to 127.0.0.1 is still not this service; another origin may not write.
  expect(http(port, "PATCH", "/api/sensors/belt/settings", R"({"median-points": 7})", {},
              "PATCH /api/sensors/belt/settings HTTP/1.1\r\nHost: evil.example:" + std::to_string(port) +
                  "\r\nConnection: close\r\nContent-Length: 2\r\n\r\n{}"),
         403, "bad_host");
  expect(http(port, "POST", "/api/sensors/belt/actions/stop", "", {"Origin: http://evil.example"}), 403, "bad_origin");
  expect(http(port, "GET", "/", {}, {}, "NOT HTTP AT ALL\r\n\r\n"), 400, "bad_request");
  // Nothing of it reached the LS5: it still streams with its median filter as it was.
  EXPECT_TRUE(json_of(http(port, "GET", "/api/sensors/belt"))["streaming"].get<bool>());
}

// Beyond loopback a token is needed for every read, write and stream (the service sets it
// then; here it is set on a loopback server; tests/web/access_test.cpp walks every route).
TEST(WebApi, WithATokenReadsWritesAndStreamsNeedIt) {
  web::ServerOptions options;
  options.token = "0123456789abcdef0123456789abcdef";
  ApiService service(options);
  const std::uint16_t port = service.port;
  EXPECT_EQ(http(port, "GET", "/api/sensors").status, 401);
  EXPECT_EQ(http(port, "GET", "/api/sensors", "", {"Authorization: Bearer " + options.token}).status, 200);
  const Reply without = http(port, "POST", "/api/sensors/belt/actions/read");
  EXPECT_EQ(without.status, 401) << without.body;
  EXPECT_EQ(http(port, "POST", "/api/sensors/belt/actions/read", "", {"Authorization: Bearer wrong"}).status, 401);
  EXPECT_EQ(http(port, "POST", "/api/sensors/belt/actions/read", "", {"Authorization: Bearer " + options.token}).status,
            200);
  web_test::EventReader refused(port, "/api/events");
  refused.read_to_end(std::chrono::seconds(10));
  EXPECT_EQ(refused.status(), 401);
  web_test::EventReader allowed(port, "/api/events?token=" + options.token);
  EXPECT_TRUE(allowed.read_until([](const web_test::Event& event) { return event.type == "sample"; }));
}

TEST(WebApi, TokenFilesAreMadeOnceWithMode0600) {
  hub_test::TempDir dir;
  const std::string path = (dir.path / "token").string();
  auto made = web::load_or_create_token(path);
  ASSERT_TRUE(made.ok()) << made.error().message;
  EXPECT_TRUE(made->created);
  EXPECT_EQ(made->value.size(), 64u);
  EXPECT_EQ(std::filesystem::status(path).permissions() & std::filesystem::perms::all,
            std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
  auto again = web::load_or_create_token(path);
  ASSERT_TRUE(again.ok());
  EXPECT_FALSE(again->created);
  EXPECT_EQ(again->value, made->value);
  std::filesystem::permissions(path, std::filesystem::perms::group_read, std::filesystem::perm_options::add);
  EXPECT_FALSE(web::load_or_create_token(path).ok());  // readable by others: refused
  EXPECT_TRUE(web::is_loopback_host("127.0.0.1"));
  EXPECT_TRUE(web::is_loopback_host("localhost"));
  EXPECT_FALSE(web::is_loopback_host("0.0.0.0"));
  EXPECT_FALSE(web::is_loopback_host("192.168.1.10"));
}

// §2 File Menu: Start Capture, Stop Capture, View Capture; downloads as SQLite, CSV, JSON lines
// and the Interface Program's .log layout per mode (U100).
TEST(WebApi, CapturesStartStopListAndDownloadInEveryFormat) {
  ApiService service;
  ASSERT_TRUE(service.all_live());
  const Reply started = http(service.port, "POST", "/api/captures", R"({"sensors": ["bay-A"]})");
  ASSERT_EQ(started.status, 201) << started.body;
  const std::string id = json_of(started)["id"];
  EXPECT_TRUE(json_of(started)["active"].get<bool>());
  // Until it has written something (bounded; the bus unit is polled many times a second).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (json_of(http(service.port, "GET", "/api/captures/" + id))["samples"].get<int>() < 5 &&
         std::chrono::steady_clock::now() < deadline) {
  }
  const Reply running_sqlite = http(service.port, "GET", "/api/captures/" + id + "/download?format=sqlite");
  EXPECT_EQ(running_sqlite.status, 409) << running_sqlite.body;  // stop it first (WAL not yet folded in)
  const Reply stopped = http(service.port, "POST", "/api/captures/" + id + "/stop");
  ASSERT_EQ(stopped.status, 200) << stopped.body;
  EXPECT_FALSE(json_of(stopped)["active"].get<bool>());
  const auto samples = json_of(stopped)["samples"].get<std::size_t>();
  EXPECT_GE(samples, 5u);
  EXPECT_EQ(json_of(http(service.port, "GET", "/api/captures"))["captures"].size(), 1u);

  const Reply sqlite = http(service.port, "GET", "/api/captures/" + id + "/download?format=sqlite");
  ASSERT_EQ(sqlite.status, 200);
  EXPECT_EQ(sqlite.body.substr(0, 16), std::string("SQLite format 3\0", 16));
  EXPECT_EQ(sqlite.headers.at("content-disposition"), "attachment; filename=\"" + id + ".sqlite\"");
  const Reply csv = http(service.port, "GET", "/api/captures/" + id + "/download?format=csv");
  ASSERT_EQ(csv.status, 200);
  EXPECT_EQ(csv.body.substr(0, 18), "time,device,addres");
  const Reply jsonl = http(service.port, "GET", "/api/captures/" + id + "/download?format=jsonl");
  ASSERT_EQ(jsonl.status, 200);
  EXPECT_NE(jsonl.body.find("\"source\":\"bay-A\""), std::string::npos);  // the sensor's name
  const Reply log = http(service.port, "GET", "/api/captures/" + id + "/download?format=log");
  ASSERT_EQ(log.status, 200) << log.body;
  // §2: "Averaging Mode: Time (H:M:S:mS), Distance, Units, Intensity." One line per sample: a
  // distance with its pulse width, or a measurement error (U100), under the column line.
  std::istringstream lines(log.body);
  std::size_t data_lines = 0;
  bool columns = false;
  for (std::string line; std::getline(lines, line);) {
    if (line == "Time (H:M:S:mS), Distance, Units, Intensity") {
      columns = true;
      continue;
    }
    const bool distance = std::regex_match(line, std::regex(R"(\d\d:\d\d:\d\d:\d{3}, \d+\.\d{3}, m, \d*)"));
    const bool error = std::regex_match(line, std::regex(R"(\d\d:\d\d:\d\d:\d{3}, ERROR \d+)"));
    EXPECT_TRUE(distance || error) << line;
    EXPECT_TRUE(columns) << "a line before the column line (U121): " << line;
    ++data_lines;
  }
  EXPECT_TRUE(columns);
  EXPECT_EQ(data_lines, samples);

  // An LS5 capture has no .log layout; bad requests name the field.
  const Reply ls5 = http(service.port, "POST", "/api/captures", R"({"sensors": ["belt"]})");
  ASSERT_EQ(ls5.status, 201);
  const std::string ls5_id = json_of(ls5)["id"];
  // Holding a sample at least (bounded), so that there is an LS5 record to refuse.
  const auto ls5_deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (json_of(http(service.port, "GET", "/api/captures/" + ls5_id))["samples"].get<int>() < 1 &&
         std::chrono::steady_clock::now() < ls5_deadline) {
  }
  EXPECT_EQ(http(service.port, "POST", "/api/captures/" + ls5_id + "/stop").status, 200);
  const Reply no_log = http(service.port, "GET", "/api/captures/" + ls5_id + "/download?format=log");
  EXPECT_EQ(no_log.status, 409) << no_log.body;
  EXPECT_NE(no_log.body.find("a ls5 capture has no .log layout"), std::string::npos) << no_log.body;
  EXPECT_EQ(error_field(http(service.port, "GET", "/api/captures/" + id + "/download?format=xls")), "format");
  EXPECT_EQ(error_field(http(service.port, "POST", "/api/captures", R"({"sensors": ["nope"]})")), "sensors");
  EXPECT_EQ(http(service.port, "GET", "/api/captures/none").status, 404);
}

// Downloads of one stopped capture at once: six of one format, for each format, then four of
// every format together. Each is answered with the whole file, the same for every download of
// a format, and the service goes on answering.
TEST(WebApi, ParallelDownloadsOfOneCaptureAreWholeAndTheSame) {
  ApiService service;
  const std::set<std::string> ulses = {"silo", "bay-A", "bay-B", "bay-C", "bay-D"};  // .log is a ULS layout
  const Reply started =
      http(service.port, "POST", "/api/captures", R"({"sensors": ["silo", "bay-A", "bay-B", "bay-C", "bay-D"]})");
  ASSERT_EQ(started.status, 201) << started.body;
  const std::string id = json_of(started)["id"];
  // The capture subscribed first: what this stream shows, it holds once stopped.
  web_test::EventReader events(service.port, "/api/events");
  std::size_t seen = 0;
  ASSERT_TRUE(events.read_until(
      [&](const web_test::Event& event) {
        if (event.type == "sample" &&
            ulses.count(nlohmann::json::parse(event.data)["sensor"].get<std::string>()) != 0) {
          ++seen;
        }
        return seen >= 150;
      },
      std::chrono::seconds(60)));
  events.close();
  const Reply stopped = http(service.port, "POST", "/api/captures/" + id + "/stop");
  ASSERT_EQ(stopped.status, 200) << stopped.body;
  const auto samples = json_of(stopped)["samples"].get<std::size_t>();
  ASSERT_GE(samples, 150u);

  const auto download_at_once = [&](const std::vector<std::string>& formats) {
    std::vector<Reply> replies(formats.size());
    std::latch go(static_cast<std::ptrdiff_t>(formats.size()));
    std::vector<std::thread> clients;
    for (std::size_t i = 0; i < formats.size(); ++i) {
      clients.emplace_back([&, i] {
        go.arrive_and_wait();
        replies[i] = http(service.port, "GET", "/api/captures/" + id + "/download?format=" + formats[i]);
      });
    }
    for (std::thread& client : clients) client.join();
    return replies;
  };
  std::map<std::string, std::string> bodies;
  const auto check = [&](const std::vector<std::string>& formats, const std::vector<Reply>& replies) {
    for (std::size_t i = 0; i < formats.size(); ++i) {
      ASSERT_EQ(replies[i].status, 200) << formats[i] << ": " << replies[i].body;
      EXPECT_EQ(replies[i].headers.at("content-length"), std::to_string(replies[i].body.size())) << formats[i];
      const std::string& body = bodies.try_emplace(formats[i], replies[i].body).first->second;
      EXPECT_TRUE(replies[i].body == body)
          << formats[i] << ": " << replies[i].body.size() << " bytes, not " << body.size();
    }
  };
  const std::vector<std::string> all = {"csv", "jsonl", "log", "sqlite"};
  for (const std::string& format : all) {
    const std::vector<std::string> same(6, format);
    check(same, download_at_once(same));
  }
  std::vector<std::string> mixed;
  for (int round = 0; round < 4; ++round) mixed.insert(mixed.end(), all.begin(), all.end());
  check(mixed, download_at_once(mixed));
  if (HasFatalFailure()) return;

  const std::string& csv = bodies["csv"];
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), samples + 1);
  EXPECT_NE(bodies["jsonl"].find("\"source\":\"bay-A\""), std::string::npos);
  EXPECT_NE(bodies["log"].find("Time (H:M:S:mS)"), std::string::npos);
  EXPECT_EQ(bodies["sqlite"].substr(0, 16), std::string("SQLite format 3\0", 16));
  // Still answering, and a later download is the same file.
  EXPECT_EQ(http(service.port, "GET", "/healthz").status, 200);
  const Reply later = http(service.port, "GET", "/api/captures/" + id + "/download?format=csv");
  ASSERT_EQ(later.status, 200);
  EXPECT_TRUE(later.body == csv);
}

// The same TOML as `rangekit ls5 config save/load` (§2 File Menu's configuration file).
TEST(WebApi, ConfigurationExportAndImport) {
  ApiService service;
  ASSERT_TRUE(service.all_live());
  const Reply exported = http(service.port, "POST", "/api/sensors/belt/config");
  ASSERT_EQ(exported.status, 200) << exported.body;
  EXPECT_EQ(exported.headers.at("content-type"), "application/toml");
  std::string toml = exported.body;
  const auto at = toml.find("median-points = ");
  ASSERT_NE(at, std::string::npos) << toml;
  toml.replace(at, toml.find('\n', at) - at, "median-points = 9");
  const Reply imported = http(service.port, "PUT", "/api/sensors/belt/config", toml);
  ASSERT_EQ(imported.status, 200) << imported.body;
  EXPECT_EQ(json_of(imported)["median-points"], 9);
  const Reply broken = http(service.port, "PUT", "/api/sensors/belt/config", "median-points = [");
  EXPECT_EQ(broken.status, 400) << broken.body;
  const Reply uls = http(service.port, "POST", "/api/sensors/bay-D/config");
  ASSERT_EQ(uls.status, 200) << uls.body;
  EXPECT_NE(uls.body.find("[settings]"), std::string::npos);
}

}  // namespace

namespace token_file_test {

using rangekit::web::load_or_create_token;

std::string refusal(const std::string& path) {
  auto token = load_or_create_token(path);
  EXPECT_FALSE(token.ok()) << path << " was taken: " << (token.ok() ? token->value : "");
  return token.ok() ? std::string() : token.error().message;
}

bool mentions(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Someone who may write the folder could plant a link to a file they cannot read; the
// token the service takes must be the file itself.
TEST(TokenFile, ASymbolicLinkIsRefusedNotFollowed) {
  hub_test::TempDir dir;
  const std::string target = (dir.path / "elsewhere").string();
  ASSERT_TRUE(load_or_create_token(target).ok());
  const std::string link = (dir.path / "token").string();
  std::filesystem::create_symlink(target, link);
  const std::string message = refusal(link);
  EXPECT_TRUE(mentions(message, link) && mentions(message, "symbolic link")) << message;
}

TEST(TokenFile, AFileThatIsNotRegularIsRefused) {
  hub_test::TempDir dir;
  const std::string path = (dir.path / "token").string();
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  // A writer holds it open with a token-like line waiting, so a read would not block.
  const int writer = ::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  ASSERT_GE(writer, 0);
  const std::string line = "0123456789abcdef0123456789abcdef\n";
  ASSERT_EQ(::write(writer, line.data(), line.size()), static_cast<ssize_t>(line.size()));
  const std::string message = refusal(path);
  ::close(writer);
  EXPECT_TRUE(mentions(message, path) && mentions(message, "not a regular file")) << message;
}

TEST(TokenFile, AModeOpenToGroupOrOthersIsRefusedSayingChmod600) {
  hub_test::TempDir dir;
  const std::string path = (dir.path / "token").string();
  ASSERT_TRUE(load_or_create_token(path).ok());
  for (const mode_t mode : {0640, 0620, 0604, 0602}) {
    ASSERT_EQ(::chmod(path.c_str(), mode), 0);
    const std::string message = refusal(path);
    EXPECT_TRUE(mentions(message, path) && mentions(message, "chmod 600")) << std::oct << mode << ": " << message;
  }
  ASSERT_EQ(::chmod(path.c_str(), 0600), 0);
  EXPECT_TRUE(load_or_create_token(path).ok());
}

TEST(TokenFile, AFileOfAnotherUserIsRefused) {
  if (::geteuid() != 0) GTEST_SKIP() << "giving a file to another user needs root";
  hub_test::TempDir dir;
  const std::string path = (dir.path / "token").string();
  ASSERT_TRUE(load_or_create_token(path).ok());
  ASSERT_EQ(::chown(path.c_str(), 65534, 65534), 0);  // nobody
  const std::string message = refusal(path);
  EXPECT_TRUE(mentions(message, path) && mentions(message, "uid 65534") && mentions(message, "chown")) << message;
}

}  // namespace token_file_test
