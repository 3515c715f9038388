// The bridge tests' rig: an LS5 emulator on a pty as a one-sensor site, and helpers to read
// what a subscriber heard and to wait on the bridge's counters.
#pragma once

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "ls5_driver/cli_process.hpp"
#include "mqtt/mqtt_fixture.hpp"
#include "rangekit/hub/hub.hpp"
#include "rangekit/mqtt/bridge.hpp"
#include "rangekit/sim/control_socket.hpp"

namespace mqtt_test {

using namespace rangekit;
using ls5_driver_test::Child;
using ls5_driver_test::TempDir;

inline std::string written(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path.string();
}

// An LS5 with range 0-50 mm (model LS5-0/50) and its target fixed at 20 mm, noise off:
// §8 formula (8.1) "distance = range · code / 50000" gives code 20000 and 20 mm.
struct Ls5 {
  TempDir temp;
  std::string port = (temp.path / "ls5").string();
  std::string control = (temp.path / "ls5.control").string();
  std::string scene = written(temp.path / "scene.toml", "[target]\nposition_mm = 20.0\nnoise_mm = 0.0\n");
  Child sim{
      {"sim", "ls5", "--port", port, "--model", "LS5-0/50-232-U10-2-24-A", "--scene", scene, "--control", control}};
  hub::SiteConfig site;
  Ls5() {
    EXPECT_NE(sim.read_line().find("ready"), std::string::npos);
    auto parsed = hub::parse_site_config(
        "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"" + port + "\"\naddress = 1\n", "site.toml");
    EXPECT_TRUE(parsed.ok());
    if (parsed) site = *parsed;
  }
  nlohmann::json outputs() const {
    auto client = ControlClient::connect(control);
    if (!client) return {};
    auto reply = client->request({{"cmd", "outputs"}});
    if (!reply) return {};
    return reply->contains("devices") ? (*reply)["devices"][0] : *reply;
  }
  void move_target(double position_mm) const {
    auto client = ControlClient::connect(control);
    ASSERT_TRUE(client.ok());
    ASSERT_TRUE(client->request({{"cmd", "move_target"}, {"position_mm", position_mm}}).ok());
  }
};

inline mqtt::BridgeOptions options_for(const Broker& broker, double max_rate_hz) {
  mqtt::BridgeOptions options;
  options.config.broker = broker.url();
  options.config.max_rate_hz = max_rate_hz;
  return options;
}

inline std::vector<nlohmann::json> payloads_on(const std::vector<Heard>& heard, const std::string& topic) {
  std::vector<nlohmann::json> out;
  for (const Heard& message : heard) {
    if (message.topic == topic) out.push_back(nlohmann::json::parse(message.payload, nullptr, false));
  }
  return out;
}

inline const Heard* find(const std::vector<Heard>& heard, const std::string& topic) {
  for (const Heard& message : heard) {
    if (message.topic == topic) return &message;
  }
  return nullptr;
}

// Waits for the first message heard on `topic` and gives it as JSON (null when none came).
inline nlohmann::json first_json_on(Subscriber& client, const std::string& topic) {
  EXPECT_TRUE(client.wait_for([&](const auto& heard) { return find(heard, topic) != nullptr; })) << topic;
  const auto heard = client.heard();
  const Heard* message = find(heard, topic);
  return message == nullptr ? nlohmann::json{} : nlohmann::json::parse(message->payload);
}

// Polls the bridge's counters (they have no event to wait on); the deadline is a safety net.
template <class Done>
inline bool until(Done done, std::chrono::seconds limit = 90s) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(20ms);
  }
  return true;
}

}  // namespace mqtt_test
