// `rangekit serve` with its MQTT face, as a process: `[mqtt]` checked by
// --check, the will marking a kill -9'd service offline, and refused credentials
// reported once in the log and on /healthz.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>

#include "ls5_driver/cli_process.hpp"
#include "mqtt/mqtt_fixture.hpp"
#include "web/http_client.hpp"

namespace {

using ls5_driver_test::Child;
using ls5_driver_test::run_cli;
using ls5_driver_test::TempDir;
using mqtt_test::Broker;
using mqtt_test::Heard;
using mqtt_test::Subscriber;
using namespace std::chrono_literals;

// Owner only, as a site file holding a broker password must be.
std::string write_site(const TempDir& dir, const std::string& text) {
  const auto path = (dir.path / "site.toml").string();
  std::ofstream(path) << text;
  std::filesystem::permissions(path, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
  return path;
}

const std::string sensor = "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"/dev/x\"\n";

TEST(ServeMqtt, CheckValidatesTheMqttTableWithClearErrors) {
  TempDir dir;
  auto run = run_cli(dir.path, {"serve", "--check",
                                write_site(dir,
                                           "[mqtt]\nbroker = \"mqtt://10.0.0.5:1884\"\nbase_topic = "
                                           "\"plant/site-3/rangekit\"\nmax_rate_hz = 5\n" +
                                               sensor)});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("mqtt mqtt://10.0.0.5:1884 as rangekit: plant/site-3/rangekit/<sensor>/..."),
            std::string::npos)
      << run.out;
  const auto refused = [&](const std::string& table, const std::string& message) {
    const auto result = run_cli(dir.path, {"serve", "--check", write_site(dir, "[mqtt]\n" + table + sensor)});
    EXPECT_EQ(result.exit_code, 3) << table;
    EXPECT_NE(result.err.find(message), std::string::npos) << result.err;
  };
  refused("broker = \"tcp://h:1883\"\n", "site.toml:2: broker 'tcp://h:1883': give mqtt://HOST[:PORT]");
  refused("broker = \"mqtt://h:99999\"\n", "the port '99999' is not 1-65535");
  refused("qos_reading = 3\n", "site.toml:2: qos_reading = 3: a QoS is 0, 1 or 2");
  refused("base_topic = \"rangekit/#\"\n", "base_topic 'rangekit/#': topic levels without '+', '#'");
  refused("max_rate_hz = -1\n", "max_rate_hz");
  refused("queue_limit = 0\n", "queue_limit = 0: 1 to 10000000 messages per sensor");
  refused("password = \"x\"\n", "[mqtt] password needs a username");
  refused("brokr = \"mqtt://h\"\n", "unknown key 'brokr' in [mqtt]");
  refused("ca_file = \"ca.pem\"\nbroker = \"mqtt://h\"\n", "ca_file needs an mqtts:// broker");
  refused("spool = true\n",
          "[mqtt] spool = true keeps each reading until the broker acknowledges it: it needs "
          "qos_reading = 1 or 2");
  refused("spool = \"yes\"\nqos_reading = 1\n", "spool");
  refused("spool = true\nqos_reading = 1\nspool_max_mb = 0\n", "spool_max_mb = 0: 1 to 1048576 MB");
  // --mqtt is checked like the file's broker.
  const auto bad_flag =
      run_cli(dir.path, {"serve", "--config", write_site(dir, sensor), "--mqtt", "http://h", "--duration", "1"});
  EXPECT_EQ(bad_flag.exit_code, 3);
  EXPECT_NE(bad_flag.err.find("--mqtt: broker 'http://h'"), std::string::npos) << bad_flag.err;
}

struct Service {
  TempDir temp;
  std::string port = (temp.path / "ls5").string();
  Child sim{{"sim", "ls5", "--port", port}};
  std::string site;
  std::unique_ptr<Child> service;
  std::uint16_t api_port = 0;
  std::string log;

  explicit Service(const std::string& mqtt_table) {
    EXPECT_NE(sim.read_line().find("ready"), std::string::npos);
    site = write_site(temp, mqtt_table + "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"" + port + "\"\n");
    service = std::make_unique<Child>(
        std::vector<std::string>{"serve", "--config", site, "--listen", "127.0.0.1:0", "--duration", "300"});
  }
  // Reads the log up to the line holding `text` (and the API line), keeping it all.
  bool read_until(const std::string& text) {
    bool found = log.find(text) != std::string::npos;
    while (!found || api_port == 0) {
      const std::string line = service->read_line();
      if (line.empty()) return false;
      log += line;
      const auto at = line.find("API on http://127.0.0.1:");
      if (at != std::string::npos) api_port = static_cast<std::uint16_t>(std::stoi(line.substr(at + 24)));
      found = found || line.find(text) != std::string::npos;
    }
    return true;
  }
  nlohmann::json health() const {
    const auto reply = web_test::http(api_port, "GET", "/healthz");
    return nlohmann::json::parse(reply.body, nullptr, false);
  }
};

TEST(ServeMqtt, AKilledServiceIsMarkedOfflineByItsWill) {
  Broker broker;
  Service service("[mqtt]\nbroker = \"" + broker.url() + "\"\n");
  ASSERT_TRUE(service.read_until("mqtt: connected")) << service.log;
  Subscriber watcher(broker.port(), {"rangekit/belt/availability"});
  ASSERT_TRUE(watcher.wait_for([](const auto& heard) { return !heard.empty() && heard.back().payload == "online"; }));
  service.service->kill_hard();  // kill -9: no clean offline from the service itself
  ASSERT_TRUE(watcher.wait_for([](const auto& heard) { return heard.back().payload == "offline"; }))
      << "the broker did not publish the will";
  // Retained: a subscriber that comes later learns it too.
  Subscriber later(broker.port(), {"rangekit/belt/availability"});
  ASSERT_TRUE(later.wait_for([](const auto& heard) { return !heard.empty(); }));
  EXPECT_EQ(later.heard().front().payload, "offline");
  EXPECT_TRUE(later.heard().front().retained);
}

TEST(ServeMqtt, RefusedCredentialsGiveOneClearErrorInTheLogAndOnHealthz) {
  Broker broker("plant", "right-password");
  Service service("[mqtt]\nbroker = \"" + broker.url() + "\"\nusername = \"plant\"\npassword = \"wrong\"\n" +
                  "reconnect_max_s = 1\n");
  ASSERT_TRUE(service.read_until("refused the credentials")) << service.log;
  // Retried with backoff, quietly: wait for more refusals, then count the log's lines about it.
  nlohmann::json mqtt;
  const auto deadline = std::chrono::steady_clock::now() + 90s;
  while (std::chrono::steady_clock::now() < deadline) {
    const auto health = service.health();
    if (health.is_object() && health.contains("mqtt") && health["mqtt"]["refusals"].get<int>() >= 3) {
      mqtt = health["mqtt"];
      EXPECT_EQ(health["status"], "degraded");
      break;
    }
    std::this_thread::sleep_for(50ms);  // polls the counter; the deadline is a safety net
  }
  ASSERT_TRUE(mqtt.is_object()) << "no third refusal";
  EXPECT_EQ(mqtt["ok"], false);
  EXPECT_EQ(mqtt["connected"], false);
  const std::string error = mqtt["error"];
  EXPECT_NE(error.find("refused the credentials of user 'plant'"), std::string::npos) << error;
  EXPECT_NE(error.find("check [mqtt] username and password"), std::string::npos) << error;
  service.service->terminate();
  for (std::string line = service.service->read_line(); !line.empty(); line = service.service->read_line()) {
    service.log += line;
  }
  std::size_t lines = 0;
  for (std::size_t at = service.log.find("mqtt: broker"); at != std::string::npos;
       at = service.log.find("mqtt: broker", at + 1)) {
    ++lines;
  }
  EXPECT_EQ(lines, 1u) << service.log;
}

}  // namespace

namespace {

// "With --demo and no URL it starts a local mosquitto too, when one is
// installed, so a newcomer can watch with mosquitto_sub -v -t 'rangekit/#'".
TEST(ServeMqtt, TheDemoStartsALocalBrokerAndPrintsHowToWatchIt) {
  Child service({"serve", "--demo", "--duration", "120", "--listen", "127.0.0.1:0"});
  std::string log;
  std::uint16_t port = 0;
  for (std::string line = service.read_line(); !line.empty() && port == 0; line = service.read_line()) {
    log += line;
    const std::string watch = "mosquitto_sub -h 127.0.0.1 -p ";
    const auto at = line.find(watch);
    if (at != std::string::npos && line.find(" -v -t 'rangekit/#'") != std::string::npos) {
      port = static_cast<std::uint16_t>(std::stoi(line.substr(at + watch.size())));
    }
  }
  ASSERT_NE(port, 0) << log;
  Subscriber watcher(port, {"rangekit/#"});
  ASSERT_TRUE(watcher.wait_for([](const std::vector<Heard>& heard) {
    bool belt = false;
    bool silo = false;
    for (const Heard& message : heard) {
      belt = belt || message.topic == "rangekit/belt/reading";
      silo = silo || message.topic == "rangekit/silo/availability";
    }
    return belt && silo;
  }));
  service.terminate();
  EXPECT_EQ(service.wait(), 130) << log;  // interrupted: exit_interrupted
}

}  // namespace
