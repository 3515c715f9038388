// Suspect samples in the service (U102, L71): the hub marks them before the ring, streams
// and captures see them, and a sensor with `drop_suspect = true` publishes none, counting them.
// Both LS5 emulators jump 160 mm every second, far beyond the default 0.2 m/s max_speed.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "hub/site_fixture.hpp"
#include "rangekit/hub/hub.hpp"

namespace {

using namespace rangekit;
using namespace rangekit::hub;
using namespace std::chrono_literals;
using hub_test::ready;
using ls5_driver_test::Child;
using ls5_driver_test::TempDir;

constexpr const char* jumping_scene = R"toml(
[target]
path = [[0.0, 120.0], [1.0, 120.0], [1.001, 280.0], [2.0, 280.0], [2.001, 120.0]]
repeat = true
)toml";

TEST(SuspectHub, U102_L71_SuspectSamplesAreMarkedOrLeftOutPerSensor) {
  const TempDir temp;
  const auto scene = (temp.path / "scene.toml").string();
  std::ofstream(scene) << jumping_scene;
  const auto marked_port = (temp.path / "marked").string();
  const auto dropped_port = (temp.path / "dropped").string();
  Child marked_sim({"sim", "ls5", "--port", marked_port, "--model", "100/200", "--scene", scene});
  Child dropped_sim({"sim", "ls5", "--port", dropped_port, "--model", "100/200", "--scene", scene});
  ASSERT_TRUE(ready(marked_sim) && ready(dropped_sim));
  auto site = parse_site_config("[[sensor]]\nname = \"marked\"\nfamily = \"ls5\"\nport = \"" + marked_port +
                                    "\"\n[[sensor]]\nname = \"dropped\"\nfamily = \"ls5\"\nport = \"" + dropped_port +
                                    "\"\ndrop_suspect = true\n",
                                "site.toml");
  ASSERT_TRUE(site.ok()) << site.error().message;
  auto hub = Hub::start(*site);
  auto all = hub->subscribe("", 100000, OverflowPolicy::drop_oldest);
  ASSERT_TRUE(all.ok());

  int marked_suspect = 0;
  int dropped_published_suspect = 0;
  int dropped_samples = 0;
  const auto deadline = std::chrono::steady_clock::now() + 60s;  // a safety net, not a wait
  while (std::chrono::steady_clock::now() < deadline) {
    for (const HubItemPtr& item : (*all)->take(1024, 200ms)) {
      const auto* sample = std::get_if<Sample>(&item->item);
      if (sample == nullptr) continue;
      if (item->sensor == "marked" && sample->suspect) {
        ++marked_suspect;
        EXPECT_EQ(sample->suspect_reason.rfind("jump: ", 0), 0u) << sample->suspect_reason;
      }
      if (item->sensor == "dropped") {
        ++dropped_samples;
        if (sample->suspect) ++dropped_published_suspect;
      }
    }
    if (marked_suspect > 0 && hub->sensor("dropped")->health.dropped_suspect > 0 && dropped_samples > 0) break;
  }
  EXPECT_GT(marked_suspect, 0);
  EXPECT_EQ(dropped_published_suspect, 0);
  const SensorSnapshot dropped = *hub->sensor("dropped");
  EXPECT_GT(dropped.health.dropped_suspect, 0u);
  EXPECT_EQ(dropped.health.suspect, dropped.health.dropped_suspect);
  const SensorSnapshot marked = *hub->sensor("marked");
  EXPECT_GT(marked.health.suspect, 0u);
  EXPECT_EQ(marked.health.dropped_suspect, 0u);
  hub->stop();
}

}  // namespace
