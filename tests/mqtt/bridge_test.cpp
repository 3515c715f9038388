// The MQTT bridge against a real mosquitto and an LS5 emulator on a pty: readings, windows,
// retained state and discovery, `set` and `action` checked on the emulator's side, and a
// broker killed and restarted mid-stream.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <functional>
#include <iostream>
#include <mutex>
#include <thread>

#include "ls5_driver/cli_process.hpp"
#include "mqtt/bridge_rig.hpp"
#include "mqtt/mqtt_fixture.hpp"
#include "rangekit/hub/hub.hpp"
#include "rangekit/mqtt/bridge.hpp"
#include "rangekit/sim/control_socket.hpp"

namespace {

using namespace rangekit;
using namespace std::chrono_literals;
using ls5_driver_test::Child;
using ls5_driver_test::TempDir;
using mqtt_test::Broker;
using mqtt_test::find;
using mqtt_test::first_json_on;
using mqtt_test::Heard;
using mqtt_test::Ls5;
using mqtt_test::options_for;
using mqtt_test::payloads_on;
using mqtt_test::Subscriber;
using mqtt_test::until;
using mqtt_test::written;

// Sets a 4 KB send buffer on every TCP socket of this process connected to 127.0.0.1:`port`;
// returns how many there were.
int shrink_send_buffers(std::uint16_t port) {
  int found = 0;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd")) {
    int fd = -1;
    try {
      fd = std::stoi(entry.path().filename().string());
    } catch (const std::exception&) {
      continue;
    }
    sockaddr_in peer{};
    socklen_t length = sizeof peer;
    int type = 0;
    socklen_t type_length = sizeof type;
    if (::getsockopt(fd, SOL_SOCKET, SO_TYPE, &type, &type_length) != 0 || type != SOCK_STREAM) continue;
    if (::getpeername(fd, reinterpret_cast<sockaddr*>(&peer), &length) != 0 || peer.sin_family != AF_INET ||
        ntohs(peer.sin_port) != port) {
      continue;
    }
    const int size = 4096;
    if (::setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &size, sizeof size) == 0) ++found;
  }
  return found;
}

// A log the test can read while the bridge writes it (from the network thread).
struct Log {
  std::mutex mutex;
  std::vector<std::string> lines;
  std::function<void(const std::string&)> sink() {
    return [this](const std::string& line) {
      const std::lock_guard lock(mutex);
      lines.push_back(line);
    };
  }
  std::string text() {
    const std::lock_guard lock(mutex);
    std::string all;
    for (const auto& line : lines) all += line + "\n";
    return all;
  }
};

TEST(MqttBridge, ReadingsCarryTheScenesDistanceAndNoSignalIsNeverADistance) {
  Broker broker;
  Ls5 ls5;
  auto hub = hub::Hub::start(ls5.site);
  Subscriber subscriber(broker.port(), {"rangekit/belt/reading"});
  ASSERT_TRUE(subscriber.wait_subscribed());
  auto bridge = mqtt::Bridge::start(*hub, options_for(broker, 0));  // every sample
  ASSERT_TRUE(bridge.ok()) << bridge.error().message;
  const auto with_distance = [](const std::vector<Heard>& heard) {
    return std::count_if(heard.begin(), heard.end(),
                         [](const Heard& m) { return m.payload.find("\"distance_mm\":20") != std::string::npos; }) >= 5;
  };
  ASSERT_TRUE(subscriber.wait_for(with_distance)) << subscriber.heard().size() << " readings";
  for (const auto& reading : payloads_on(subscriber.heard(), "rangekit/belt/reading")) {
    ASSERT_TRUE(reading.is_object());
    EXPECT_EQ(reading["kind"], "result");
    if (reading["signal"] == "ok") {
      EXPECT_EQ(reading["code"], 20000);
      EXPECT_DOUBLE_EQ(reading["distance_mm"].get<double>(), 20.0);
    }
  }
  // Beyond the range: §8 "65535 – to indicate that there is no signal." (L77) The reading says
  // so, with no distance at all.
  subscriber.clear();
  ls5.move_target(80.0);
  ASSERT_TRUE(subscriber.wait_for([](const std::vector<Heard>& heard) {
    return std::count_if(heard.begin(), heard.end(), [](const Heard& m) {
             return m.payload.find("\"signal\":\"lost\"") != std::string::npos;
           }) >= 3;
  }));
  for (const auto& reading : payloads_on(subscriber.heard(), "rangekit/belt/reading")) {
    if (reading["signal"] != "lost") continue;
    EXPECT_EQ(reading["code"], 65535);
    EXPECT_TRUE(reading["distance_mm"].is_null()) << reading.dump();
  }
  (*bridge)->stop();
}

TEST(MqttBridge, AboveTheRateOneWindowMessageWithCountMinMeanMaxLastAndQuality) {
  Broker broker;
  Ls5 ls5;
  auto hub = hub::Hub::start(ls5.site);
  Subscriber subscriber(broker.port(), {"rangekit/belt/reading"});
  ASSERT_TRUE(subscriber.wait_subscribed());
  auto bridge = mqtt::Bridge::start(*hub, options_for(broker, 2));  // at most 2 messages a second
  ASSERT_TRUE(bridge.ok()) << bridge.error().message;
  const auto windows = [](const std::vector<Heard>& heard, const char* needle) {
    return std::count_if(heard.begin(), heard.end(), [&](const Heard& m) {
      return m.payload.find("\"window\":true") != std::string::npos && m.payload.find(needle) != std::string::npos;
    });
  };
  ASSERT_TRUE(subscriber.wait_for([&](const auto& heard) { return windows(heard, "\"last\":20.0") >= 2; }));
  for (const auto& window : payloads_on(subscriber.heard(), "rangekit/belt/reading")) {
    if (!window.contains("window") || window["readings"] == 0) continue;
    EXPECT_GT(window["count"].get<int>(), 1) << window.dump();
    EXPECT_EQ(window["unit"], "mm");
    EXPECT_DOUBLE_EQ(window["min"].get<double>(), 20.0) << window.dump();
    EXPECT_DOUBLE_EQ(window["mean"].get<double>(), 20.0) << window.dump();
    EXPECT_DOUBLE_EQ(window["max"].get<double>(), 20.0) << window.dump();
  }
  // No signal (L77): counted in the window, and no distance from it.
  subscriber.clear();
  ls5.move_target(80.0);
  ASSERT_TRUE(subscriber.wait_for([&](const auto& heard) { return windows(heard, "\"readings\":0") >= 1; }));
  for (const auto& window : payloads_on(subscriber.heard(), "rangekit/belt/reading")) {
    if (!window.contains("window") || window["readings"] != 0) continue;
    EXPECT_EQ(window["no_signal"], window["count"]) << window.dump();
    EXPECT_TRUE(window["last"].is_null() && window["min"].is_null()) << window.dump();
  }
  (*bridge)->stop();
}

TEST(MqttBridge, RetainedStatusAvailabilityAndDiscoveryAreThereForALateSubscriber) {
  Broker broker;
  Ls5 ls5;
  auto hub = hub::Hub::start(ls5.site);
  auto bridge = mqtt::Bridge::start(*hub, options_for(broker, 10));
  ASSERT_TRUE(bridge.ok()) << bridge.error().message;
  // A subscriber that comes later gets the retained messages from the broker.
  {
    // Once the sensor is connected and identified, both went out (retained).
    Subscriber probe(broker.port(), {"rangekit/belt/availability", "rangekit/belt/status"});
    ASSERT_TRUE(probe.wait_for([](const auto& heard) {
      bool online = false;
      bool identified = false;
      for (const Heard& message : heard) {
        if (message.topic == "rangekit/belt/availability") online = message.payload == "online";
        if (message.topic == "rangekit/belt/status") {
          identified = message.payload.find("\"serial\":157") != std::string::npos;
        }
      }
      return online && identified;
    }));
  }
  Subscriber late(broker.port(), {"rangekit/belt/status", "rangekit/belt/availability", "homeassistant/#"});
  const std::string distance = "homeassistant/sensor/rangekit_belt/distance/config";
  ASSERT_TRUE(late.wait_for([&](const auto& heard) {
    return find(heard, "rangekit/belt/status") != nullptr && find(heard, distance) != nullptr &&
           find(heard, "homeassistant/sensor/rangekit_belt/errors/config") != nullptr &&
           find(heard, "homeassistant/sensor/rangekit_belt/rate/config") != nullptr &&
           find(heard, "homeassistant/button/rangekit_belt/action_latch_read/config") != nullptr &&
           find(heard, "homeassistant/button/rangekit_belt/action_single/config") != nullptr;
  }));
  const auto heard = late.heard();
  const Heard* availability = find(heard, "rangekit/belt/availability");
  ASSERT_NE(availability, nullptr);
  EXPECT_TRUE(availability->retained);
  EXPECT_EQ(availability->payload, "online");
  const Heard* status = find(heard, "rangekit/belt/status");
  EXPECT_TRUE(status->retained);
  const auto status_json = nlohmann::json::parse(status->payload);
  EXPECT_EQ(status_json["name"], "belt");
  EXPECT_EQ(status_json["identity"]["serial"], 157);  // `sim ls5` default serial number (its --help)
  // The address as the API spells it (docs/api.md): the LS5's in decimal, the byte apart.
  EXPECT_EQ(status_json["address"], "1");
  EXPECT_EQ(status_json["address_code"], 1);
  EXPECT_TRUE(status_json["health"]["connected"].get<bool>());
  const Heard* config = find(heard, distance);
  EXPECT_TRUE(config->retained);
  const auto entity = nlohmann::json::parse(config->payload);
  EXPECT_EQ(entity["unit_of_measurement"], "mm");
  EXPECT_EQ(entity["device_class"], "distance");
  EXPECT_EQ(entity["state_topic"], "rangekit/belt/reading");
  EXPECT_EQ(entity["availability_topic"], "rangekit/belt/availability");
  EXPECT_EQ(
      nlohmann::json::parse(find(heard, "homeassistant/sensor/rangekit_belt/rate/config")->payload)["entity_category"],
      "diagnostic");
  // An LS5 has no look-down mode: no presence entity for it.
  EXPECT_EQ(find(heard, "homeassistant/binary_sensor/rangekit_belt/presence/config"), nullptr);
  // A button per action of the family and argument: the LS5's latch, alone or reading the
  // latched result (FR); no pointer, which is the ULS's.
  const auto button =
      nlohmann::json::parse(find(heard, "homeassistant/button/rangekit_belt/action_latch_read/config")->payload);
  EXPECT_EQ(button["command_topic"], "rangekit/belt/action");
  EXPECT_EQ(nlohmann::json::parse(button["payload_press"].get<std::string>()),
            (nlohmann::json{{"action", "latch"}, {"argument", "read"}}));
  EXPECT_NE(find(heard, "homeassistant/button/rangekit_belt/action_latch/config"), nullptr);
  EXPECT_EQ(find(heard, "homeassistant/button/rangekit_belt/action_pointer_on/config"), nullptr);
  // A clean stop marks the sensor offline (retained).
  Subscriber watcher(broker.port(), {"rangekit/belt/availability"});
  ASSERT_TRUE(watcher.wait_for([](const auto& h) { return find(h, "rangekit/belt/availability") != nullptr; }));
  (*bridge)->stop();
  EXPECT_TRUE(watcher.wait_for([](const auto& h) { return !h.empty() && h.back().payload == "offline"; }));
}

TEST(MqttBridge, SetReachesTheEmulatorAndAnInvalidOneGetsAnErrorAndNothingReachesIt) {
  Broker broker;
  Ls5 ls5;
  auto hub = hub::Hub::start(ls5.site);
  Subscriber client(broker.port(), {"rangekit/belt/set/result", "rangekit/belt/action/result", "rangekit/reply/test"});
  ASSERT_TRUE(client.wait_subscribed());
  auto bridge = mqtt::Bridge::start(*hub, options_for(broker, 10));
  ASSERT_TRUE(bridge.ok()) << bridge.error().message;
  ASSERT_TRUE(until([&] { return (*bridge)->stats().connected; }));
  // LS5 table 9.2, parameter 03 "Analog output is enabled/disabled"; default 01.
  ASSERT_EQ(ls5.outputs()["analog_enabled"], true);
  client.publish("rangekit/belt/set", R"({"analog-output": "disabled"})");
  ASSERT_TRUE(client.wait_for([](const auto& heard) { return find(heard, "rangekit/belt/set/result") != nullptr; }));
  auto result = nlohmann::json::parse(find(client.heard(), "rangekit/belt/set/result")->payload);
  EXPECT_EQ(result["ok"], true) << result.dump();
  EXPECT_EQ(result["settings"]["analog-output"], "disabled") << result.dump();
  EXPECT_EQ(ls5.outputs()["analog_enabled"], false);  // checked on the emulator's side

  // Table 9.2 0D, the median filter: an odd number of points (L4). An invalid request names
  // the field and its range, and nothing of it reaches the sensor, not even its valid part.
  client.clear();
  client.publish("rangekit/belt/set", R"({"analog-output": "enabled", "median-points": 8})", "rangekit/reply/test",
                 "request-17");
  ASSERT_TRUE(client.wait_for([](const auto& heard) {
    return find(heard, "rangekit/belt/set/result") != nullptr && find(heard, "rangekit/reply/test") != nullptr;
  }));
  result = nlohmann::json::parse(find(client.heard(), "rangekit/belt/set/result")->payload);
  EXPECT_EQ(result["ok"], false);
  EXPECT_EQ(result["error"]["field"], "median-points") << result.dump();
  EXPECT_NE(result["error"]["message"].get<std::string>().find("49"), std::string::npos) << result.dump();
  EXPECT_EQ(ls5.outputs()["analog_enabled"], false);
  // MQTT 5: the answer also on the response topic, with the request's correlation data.
  const auto replies = client.heard();
  const Heard* reply = find(replies, "rangekit/reply/test");
  EXPECT_EQ(reply->correlation, "request-17");
  EXPECT_EQ(nlohmann::json::parse(reply->payload)["error"]["field"], "median-points");

  client.clear();
  client.publish("rangekit/belt/set", "median-points=7");
  ASSERT_TRUE(client.wait_for([](const auto& heard) { return find(heard, "rangekit/belt/set/result") != nullptr; }));
  EXPECT_EQ(nlohmann::json::parse(find(client.heard(), "rangekit/belt/set/result")->payload)["error"]["code"],
            "bad_body");

  // Actions: stop reaches the sensor (table 9.1 SB), an unknown one is named.
  client.clear();
  client.publish("rangekit/belt/action", "stop");
  ASSERT_TRUE(client.wait_for([](const auto& heard) { return find(heard, "rangekit/belt/action/result") != nullptr; }));
  EXPECT_EQ(nlohmann::json::parse(find(client.heard(), "rangekit/belt/action/result")->payload)["ok"], true);
  EXPECT_EQ(ls5.outputs()["streaming"], false);
  client.clear();
  client.publish("rangekit/belt/action", R"({"action": "explode"})");
  EXPECT_EQ(first_json_on(client, "rangekit/belt/action/result")["error"]["code"], "unknown_action");
  (*bridge)->stop();
}

// Whatever a command's payload holds, the bridge answers with an error naming the field, and
// the next command still runs: a JSON type the request does not expect once ended the service.
TEST(MqttBridge, CommandsOfAnyJsonTypeOrBytesGetAnErrorAndTheServiceGoesOn) {
  Broker broker;
  Ls5 ls5;
  auto hub = hub::Hub::start(ls5.site);
  Subscriber client(broker.port(), {"rangekit/belt/set/result", "rangekit/belt/action/result", "elsewhere/#"});
  ASSERT_TRUE(client.wait_subscribed());
  auto bridge = mqtt::Bridge::start(*hub, options_for(broker, 10));
  ASSERT_TRUE(bridge.ok()) << bridge.error().message;
  ASSERT_TRUE(until([&] { return (*bridge)->stats().connected; }));
  ASSERT_TRUE(until([&] { return ls5.outputs()["streaming"] == true; }));
  const auto answer = [&](const std::string& topic, const std::string& payload, const std::string& response = {}) {
    client.clear();
    client.publish("rangekit/belt/" + topic, payload, response);
    return first_json_on(client, "rangekit/belt/" + topic + "/result");
  };
  struct Case {
    const char* topic;
    std::string payload;
    const char* code;
    const char* field;
  };
  const std::vector<Case> cases{
      {"action", R"({"action": 1})", "bad_body", "action"},
      {"action", R"({"action": null})", "bad_body", "action"},
      {"action", R"({"action": ["start"]})", "bad_body", "action"},
      {"action", R"({"action": "pointer", "argument": true})", "bad_body", "argument"},
      {"action", R"({"argument": "on"})", "bad_body", "action"},
      {"action", R"({"action": "start", "force": "yes"})", "bad_body", "force"},
      {"action", "[1, 2]", "bad_body", "action"},
      {"action", "17", "bad_body", "action"},
      {"action", std::string("\xff\xfe\x00\x01", 4), "unknown_action", "action"},
      {"set", R"({"analog-output": {"on": 1}})", "bad_body", "analog-output"},
      {"set", R"({"median-points": [1, "x"]})", "bad_body", "median-points"},
      {"set", "null", "bad_body", ""},
      {"set", std::string(20000, '{'), "too_large", ""},
  };
  for (const Case& c : cases) {
    const auto result = answer(c.topic, c.payload);
    EXPECT_EQ(result["ok"], false) << c.payload.substr(0, 60) << " -> " << result.dump();
    EXPECT_EQ(result["error"]["code"], c.code) << c.payload.substr(0, 60) << " -> " << result.dump();
    if (*c.field != 0) {
      EXPECT_EQ(result["error"]["field"], c.field) << c.payload.substr(0, 60) << " -> " << result.dump();
    }
    EXPECT_FALSE(result["error"]["message"].get<std::string>().empty());
  }
  // A response topic outside <base>/reply/ is refused: the service would publish anywhere its rights allow.
  const auto refused = answer("action", "stop", "elsewhere/inbox");
  EXPECT_EQ(refused["error"]["code"], "bad_response_topic") << refused.dump();
  EXPECT_EQ(find(client.heard(), "elsewhere/inbox"), nullptr);
  EXPECT_EQ(ls5.outputs()["streaming"], true);  // and nothing of it ran
  // The bridge still runs commands: stop reaches the sensor (table 9.1 SB).
  EXPECT_EQ(answer("action", R"({"action": "stop"})")["ok"], true);
  EXPECT_EQ(ls5.outputs()["streaming"], false);
  (*bridge)->stop();
}

// A flood of commands: max_queued_commands (64; 4 here) wait to run at most, and each one over
// that is answered `busy` at once, not run and not queued; every command gets an answer, and
// the bridge runs the next.
TEST(MqttBridge, AFloodOfCommandsIsAnsweredAndNoMoreThanTheBoundWait) {
  Broker broker;
  Ls5 ls5;
  auto hub = hub::Hub::start(ls5.site);
  Subscriber client(broker.port(), {"rangekit/belt/set/result"});
  ASSERT_TRUE(client.wait_subscribed());
  auto options = options_for(broker, 10);
  options.max_queued_commands = 4;
  auto bridge = mqtt::Bridge::start(*hub, options);
  ASSERT_TRUE(bridge.ok()) << bridge.error().message;
  ASSERT_TRUE(until([&] { return (*bridge)->stats().connected; }));
  ASSERT_TRUE(until([&] { return ls5.outputs()["streaming"] == true; }));
  // Each set pauses the sensor's stream to write (about a second); 40 arrive far faster.
  constexpr std::size_t flood = 40;
  for (std::size_t i = 0; i < flood; ++i) client.publish("rangekit/belt/set", R"({"analog-output": "disabled"})");
  ASSERT_TRUE(client.wait_for([&](const auto& heard) { return heard.size() >= flood; }))
      << client.heard().size() << " of " << flood << " answered";
  std::size_t done = 0;
  std::size_t busy = 0;
  for (const Heard& answer : client.heard()) {
    const auto result = nlohmann::json::parse(answer.payload);
    if (result.value("ok", false)) ++done;
    if (result.contains("error") && result["error"]["code"] == "busy") ++busy;
  }
  EXPECT_EQ(done + busy, flood);
  EXPECT_GT(busy, 0u) << "the flood never filled the queue";
  EXPECT_GE(done, 4u) << "the 4 queued were not all run";
  const auto stats = (*bridge)->stats();
  EXPECT_EQ(stats.busy, busy);
  EXPECT_EQ(stats.commands, done);
  client.clear();
  client.publish("rangekit/belt/set", R"({"analog-output": "enabled"})");
  EXPECT_EQ(first_json_on(client, "rangekit/belt/set/result")["ok"], true);
  EXPECT_EQ(ls5.outputs()["analog_enabled"], true);
  (*bridge)->stop();
}

// A command left retained on the broker is not run when the service connects (MQTT 5 retain
// handling): it would run again at every start.
TEST(MqttBridge, ARetainedCommandIsNotRunAtConnect) {
  Broker broker;
  Ls5 ls5;
  {
    Subscriber publisher(broker.port(), {"rangekit/belt/action"});
    ASSERT_TRUE(publisher.wait_subscribed());
    publisher.publish("rangekit/belt/action", "stop", {}, {}, true);
    ASSERT_TRUE(publisher.wait_for([](const auto& heard) { return find(heard, "rangekit/belt/action") != nullptr; }));
  }
  auto hub = hub::Hub::start(ls5.site);
  Subscriber client(broker.port(), {"rangekit/belt/action/result", "rangekit/belt/availability"});
  ASSERT_TRUE(client.wait_subscribed());
  auto bridge = mqtt::Bridge::start(*hub, options_for(broker, 10));
  ASSERT_TRUE(bridge.ok()) << bridge.error().message;
  ASSERT_TRUE(until([&] { return (*bridge)->stats().connected; }));
  // A live command after it is answered first: had the retained one run, its result came before.
  client.publish("rangekit/belt/action", "explode");
  EXPECT_EQ(first_json_on(client, "rangekit/belt/action/result")["error"]["code"], "unknown_action");
  (*bridge)->stop();
}

TEST(MqttBridge, BrokerKilledAndRestartedMidStreamTheServiceResumesAndCountsTheDrops) {
  Broker broker;
  Ls5 ls5;
  auto hub = hub::Hub::start(ls5.site);
  auto options = options_for(broker, 0);
  options.config.queue_limit = 5;  // a small queue, so the outage surely overflows it
  options.config.reconnect_max_s = 1;
  auto bridge = mqtt::Bridge::start(*hub, options);
  ASSERT_TRUE(bridge.ok()) << bridge.error().message;
  {
    Subscriber before(broker.port(), {"rangekit/belt/reading"});
    ASSERT_TRUE(before.wait_for([](const auto& heard) { return heard.size() >= 5; }));
  }
  broker.broker->kill_hard();
  ASSERT_TRUE(until([&] { return (*bridge)->stats().dropped > 0; })) << "nothing dropped while the broker was away";
  const auto during = hub->sensor("belt");
  EXPECT_TRUE(during->health.connected);  // the sensor never waited for the broker
  const auto records = during->health.records;
  ASSERT_TRUE(broker.broker->restart().ok());
  ASSERT_TRUE(until([&] { return (*bridge)->stats().reconnects >= 1 && (*bridge)->stats().connected; }));
  {
    Subscriber probe(broker.port(), {"rangekit/belt/status"});
    ASSERT_TRUE(probe.wait_for([](const auto& heard) { return !heard.empty(); }));
  }
  // The broker kept nothing (persistence off): what it retains now was published again after the reconnect.
  Subscriber after(broker.port(), {"rangekit/belt/reading", "rangekit/belt/status", "rangekit/belt/availability"});
  ASSERT_TRUE(after.wait_for([](const auto& heard) {
    const auto status = find(heard, "rangekit/belt/status");
    return status != nullptr && status->retained && find(heard, "rangekit/belt/availability") != nullptr &&
           std::count_if(heard.begin(), heard.end(),
                         [](const Heard& m) { return m.topic == "rangekit/belt/reading"; }) >= 5;
  })) <<
      [&] {
        std::string topics;
        for (const Heard& m : after.heard()) topics += m.topic + (m.retained ? " (retained) " : " ");
        return "heard: " + topics.substr(0, 2000) +
               "\nbroker log: " + ls5_driver_test::read_file(broker.broker->log_path());
      }();
  EXPECT_EQ(find(after.heard(), "rangekit/belt/availability")->payload, "online");
  const auto stats = (*bridge)->stats();
  EXPECT_GE(stats.reconnects, 1u);
  EXPECT_GT(stats.dropped, 0u);
  EXPECT_GT(hub->sensor("belt")->health.records, records);
  (*bridge)->stop();
}

// A broker that takes no packet over 120 bytes says so in its CONNACK (MQTT 5 Maximum Packet
// Size): the readings (about 160 bytes), the status and discovery cannot go, by the fast path
// or by libmosquitto. They are dropped and counted, said once in the log, and do not hold up
// the queue: the small availability message still arrives, and the session is never cut for
// an oversized packet.
TEST(MqttBridge, MessagesOverTheBrokersMaximumPacketSizeAreDroppedAndCountedAndHoldNothingUp) {
  Broker broker({}, {}, "max_packet_size 120\n");
  Ls5 ls5;
  auto hub = hub::Hub::start(ls5.site);
  Subscriber subscriber(broker.port(), {"rangekit/belt/#"});
  ASSERT_TRUE(subscriber.wait_subscribed());
  Log log;
  auto options = options_for(broker, 0);
  options.log = log.sink();
  auto bridge = mqtt::Bridge::start(*hub, options);
  ASSERT_TRUE(bridge.ok()) << bridge.error().message;
  // Availability may say offline first (the sensor not yet connected), then online.
  ASSERT_TRUE(subscriber.wait_for([](const auto& heard) {
    return std::any_of(heard.begin(), heard.end(),
                       [](const Heard& m) { return m.topic == "rangekit/belt/availability" && m.payload == "online"; });
  })) << log.text();
  // The bridge counts what it drops as it takes the hub's items, which can be behind the
  // hub's own count (under ThreadSanitizer it was): wait for its count, not the hub's.
  ASSERT_TRUE(until([&] { return (*bridge)->stats().dropped > 200; })) << (*bridge)->stats().dropped;
  const auto stats = (*bridge)->stats();
  EXPECT_EQ(stats.queued, 0u);
  EXPECT_EQ(stats.reconnects, 0u);
  EXPECT_TRUE(stats.connected);
  EXPECT_EQ(find(subscriber.heard(), "rangekit/belt/reading"), nullptr);
  EXPECT_EQ(find(subscriber.heard(), "rangekit/belt/status"), nullptr);
  const std::string said = log.text();
  EXPECT_NE(said.find("larger than the broker's maximum packet size"), std::string::npos) << said;
  (*bridge)->stop();
}

// A broker that stops reading without closing the connection (a host gone dead, no RST;
// here SIGSTOP). The readings fill the socket and part of a fast-path packet is left on the
// wire, which holds off libmosquitto's keepalive: the bridge must still take the session for
// lost within 1.5 keepalive periods (here 7.5 s) of the socket taking nothing (on loopback TCP never
// gives up on its own), and come back once the broker reads again.
TEST(MqttBridge, ABrokerThatStopsReadingIsTakenForLostAndTheSessionComesBack) {
  Broker broker;
  Ls5 ls5;
  auto hub = hub::Hub::start(ls5.site);
  // §8.4: t = 1 ms and every result, 1000 readings a second to fill the socket quickly.
  ASSERT_TRUE(hub->set("belt", {{"period-ms", "1"}, {"thinning", "1"}}).ok());
  auto options = options_for(broker, 0);
  options.keepalive_s = 5;  // libmosquitto takes no less
  options.reconnect_max_s = 1;
  auto bridge = mqtt::Bridge::start(*hub, options);
  ASSERT_TRUE(bridge.ok()) << bridge.error().message;
  ASSERT_TRUE(until([&] { return (*bridge)->stats().connected && (*bridge)->stats().published > 500; }, 20s))
      << "published " << (*bridge)->stats().published << " connected " << (*bridge)->stats().connected << " records "
      << hub->sensor("belt")->health.records;
  // The session's socket in this process gets a small send buffer (which also ends its
  // autotuning), so the stopped broker's receive window and it fill within a second and a
  // send() then takes part of a packet; on its own the kernel took all 1.5 MB sent in 9 s.
  ASSERT_EQ(shrink_send_buffers(broker.port()), 1) << "the bridge's session socket was not found";
  const pid_t pid = broker.broker->pid();
  struct Resume {  // SIGCONT on every way out: a stopped broker would not take its SIGTERM
    pid_t pid;
    ~Resume() { ::kill(pid, SIGCONT); }
  } resume{pid};
  ASSERT_EQ(::kill(pid, SIGSTOP), 0);
  const auto stopped_at = std::chrono::steady_clock::now();
  ASSERT_TRUE(until([&] { return !(*bridge)->stats().connected; }, 60s))
      << "the session still counts as connected to a broker that reads nothing";
  const auto noticed_after = std::chrono::steady_clock::now() - stopped_at;
  EXPECT_TRUE(hub->sensor("belt")->health.connected);  // the sensor never waited for the broker
  ::kill(pid, SIGCONT);
  ASSERT_TRUE(until([&] { return (*bridge)->stats().connected && (*bridge)->stats().reconnects >= 1; }))
      << "no reconnect after the broker read again";
  const auto published = (*bridge)->stats().published;
  EXPECT_TRUE(until([&] { return (*bridge)->stats().published > published + 500; }));
  EXPECT_GT((*bridge)->stats().dropped, 0u);
  std::cout << "lost session noticed " << std::chrono::duration<double>(noticed_after).count()
            << " s after the broker stopped reading\n";
  (*bridge)->stop();
}

}  // namespace
