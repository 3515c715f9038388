// The sensor hub against the emulators on real ptys: an LS5, a ULS and an RS-485 bus of
// four ULS units served together; settings checked before sending and read back; a killed
// emulator seen disconnected, then reconnected.
#include <gtest/gtest.h>

#include "rangekit/core/family.hpp"

#include <map>
#include <regex>

#include "hub/site_fixture.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/hub/hub.hpp"

namespace {

using namespace rangekit;
using namespace rangekit::hub;
using namespace std::chrono_literals;
using hub_test::ready;
using hub_test::Site;
using ls5_driver_test::Child;
using ls5_driver_test::TempDir;

// Takes from `subscription` until `done` says so or the deadline passes (a safety net, not a wait).
template <class Done>
bool take_until(Subscription& subscription, Done done, std::chrono::seconds limit = 60s) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < deadline) {
    for (const HubItemPtr& item : subscription.take(1024, 200ms)) {
      if (done(*item)) return true;
    }
  }
  return false;
}

std::string value_of(const std::vector<Field>& fields, const std::string& key) {
  for (const Field& field : fields) {
    if (field.key == key) return field.value;
  }
  return "<no " + key + ">";
}

TEST(HubPty, ServesAnLs5AUlsAndABusOfFourUnits) {
  Site site;
  auto hub = Hub::start(site.config);
  auto all = hub->subscribe("", 100000, OverflowPolicy::drop_oldest);
  ASSERT_TRUE(all.ok());
  std::map<std::string, int> samples;
  const bool every_sensor = take_until(**all, [&](const HubItem& item) {
    if (std::holds_alternative<Sample>(item.item)) ++samples[item.sensor];
    if (samples.size() < 6) return false;
    for (const auto& [name, count] : samples) {
      if (count < 3) return false;
    }
    return true;
  });
  EXPECT_TRUE(every_sensor) << "sensors with samples: " << samples.size();
  for (const SensorSnapshot& sensor : hub->sensors()) {
    EXPECT_TRUE(sensor.health.connected) << sensor.config.name << ": " << sensor.health.last_event;
    EXPECT_TRUE(sensor.streaming) << sensor.config.name;
    EXPECT_GE(sensor.health.records, 3u) << sensor.config.name;
    EXPECT_FALSE(sensor.identity.empty()) << sensor.config.name;
  }
  // `sim ls5` defaults: firmware LS5.12.0, serial number 157, model 8.1234/40.001 (its --help).
  const auto belt = hub->sensor("belt");
  ASSERT_TRUE(belt.ok());
  EXPECT_EQ(value_of(belt->identity, "version"), "LS5.12.0");
  EXPECT_EQ(value_of(belt->identity, "serial"), "157");
  EXPECT_EQ(value_of(belt->identity, "range-mm"), "40.001");
  EXPECT_EQ(value_of(belt->identity, "lower-boundary-mm"), "8.1234");
  EXPECT_EQ(value_of(hub->sensor("bay-C")->identity, "address"), "C");
  // Sequence numbers are one order across sensors; the ring resumes after any of them.
  const auto since = hub->since("", 0);
  ASSERT_TRUE(since.ok());
  for (std::size_t i = 1; i < since->items.size(); ++i)
    EXPECT_LT(since->items[i - 1]->sequence, since->items[i]->sequence);
  EXPECT_EQ(hub->sensor("nope").error().message,
            "no sensor named 'nope' (sensors: belt, silo, bay-A, bay-B, bay-C, bay-D)");
}

// LS5 table 9.2 (L4): the median filter takes an odd number of points, 1-49. ULS §8 Set Short
// Gate: 0-1700 (metres). A refused value sends nothing: the setting reads as before.
TEST(HubPty, SettingsAreCheckedBeforeSendingAndReadBack) {
  Site site;
  auto hub = Hub::start(site.config);
  auto before = hub->settings("belt");
  ASSERT_TRUE(before.ok()) << before.error().message;
  const std::string median_before = value_of(*before, "median-points");

  auto refused = hub->set("belt", {{"averaging-points", "4"}, {"median-points", "8"}});
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("median-points"), std::string::npos) << refused.error().message;
  auto unchanged = hub->settings("belt");
  ASSERT_TRUE(unchanged.ok());
  EXPECT_EQ(value_of(*unchanged, "median-points"), median_before);
  EXPECT_EQ(value_of(*unchanged, "averaging-points"), value_of(*before, "averaging-points"));

  auto changed = hub->set("belt", {{"median-points", "7"}});
  ASSERT_TRUE(changed.ok()) << changed.error().message;
  EXPECT_EQ(value_of(*changed, "median-points"), "7");

  auto uls_refused = hub->set("silo", {{"short-gate-m", "2000"}});
  ASSERT_FALSE(uls_refused.ok());
  EXPECT_NE(uls_refused.error().message.find("1700"), std::string::npos) << uls_refused.error().message;
  // The names `rangekit uls get` prints, with the unit in the name (docs/cli.md).
  auto uls_changed = hub->set("bay-B", {{"short-gate-m", "12.5"}, {"prf-hz", "1000"}});
  ASSERT_TRUE(uls_changed.ok()) << uls_changed.error().message;
  EXPECT_EQ(value_of(*uls_changed, "short-gate-m"), "12.5");
  EXPECT_NE(value_of(*hub->settings("bay-A"), "short-gate-m"), "12.5");  // the bus addresses one unit
  // The silo unit streams, so it measures: the set stops it for the write and restarts it (U24).
  auto while_measuring = hub->set("silo", {{"long-gate-m", "900"}});
  ASSERT_TRUE(while_measuring.ok()) << while_measuring.error().message;
  EXPECT_EQ(value_of(*while_measuring, "long-gate-m"), "900");

  auto single = hub->act("silo", "single");
  ASSERT_TRUE(single.ok()) << single.error().message;
  // §9: "Resolution 1 mm or 0.01 ft": "27.881 m", not "27.881000 m".
  EXPECT_TRUE(std::regex_match(single->text, std::regex(R"(\d+\.\d{3} m)"))) << single->text;
  // The measurement itself comes along, so a face gives its reading as a number with its unit.
  ASSERT_TRUE(single->sample.has_value());
  const auto reading = reading_of(*single->sample);
  ASSERT_TRUE(reading.has_value());
  EXPECT_EQ(reading->channel->key, "distance_m");
  EXPECT_NEAR(reading->value, std::stod(single->text), 0.0005) << single->text;
  const auto latch = hub->act("silo", "latch");
  EXPECT_EQ(latch.error().code, Errc::unknown_command);
  EXPECT_EQ(latch.error().message,
            "'latch' is not an action of uls sensor 'silo' (start, stop, read, single, pointer, save, reset)");
  EXPECT_EQ(hub->act("belt", "pointer", "on").error().code, Errc::unknown_command);
  EXPECT_EQ(hub->act("silo", "pointer", "maybe").error().message, "pointer takes on or off, not 'maybe'");
}

TEST(HubPty, AKilledEmulatorIsDisconnectedThenReconnected) {
  Site site;
  auto hub = Hub::start(site.config);
  auto belt = hub->subscribe("belt", 100000, OverflowPolicy::drop_oldest);
  ASSERT_TRUE(belt.ok());
  ASSERT_TRUE(take_until(**belt, [](const HubItem& item) { return std::holds_alternative<Sample>(item.item); }));
  site.ls5.kill_hard();
  const auto kind_is = [](StreamEventKind kind) {
    return [kind](const HubItem& item) {
      const auto* event = std::get_if<StreamEvent>(&item.item);
      return event != nullptr && event->kind == kind;
    };
  };
  ASSERT_TRUE(take_until(**belt, kind_is(StreamEventKind::disconnected)));
  EXPECT_FALSE(hub->sensor("belt")->health.connected);
  Child again({"sim", "ls5", "--port", (site.temp.path / "ls5").string()});
  ASSERT_TRUE(ready(again));
  ASSERT_TRUE(take_until(**belt, kind_is(StreamEventKind::reconnected)));
  ASSERT_TRUE(take_until(**belt, [](const HubItem& item) { return std::holds_alternative<Sample>(item.item); }));
  EXPECT_TRUE(hub->sensor("belt")->health.connected);
  EXPECT_GE(hub->sensor("belt")->health.reconnects, 1u);
}

}  // namespace

// §7: "The RS485 system will not function correctly with same address assigned to 2 or more
// units." U105: a scan lists who answers; an assign to an address a unit answers at is refused.
// U106: the site file is not followed: the unit moved to E answers there, bay-C's C is silent.
TEST(HubPty, U105_U106_ScanAndAssignOnTheBus) {
  Site site;
  auto hub = Hub::start(site.config);
  const auto addresses = [](const BusScan& scan) {
    std::string found;
    for (const BusUnitFound& unit : scan.found) found += static_cast<char>(unit.address);
    return found;
  };
  auto scan = hub->scan_bus("bay-C");
  ASSERT_TRUE(scan.ok()) << scan.error().message;
  EXPECT_EQ(addresses(*scan), "ABCD");
  EXPECT_EQ(scan->asked, 62u);  // §8 UA: a-z, A-Z, 0-9
  ASSERT_EQ(scan->site.size(), 4u);
  EXPECT_EQ(scan->site[2], (std::pair<std::uint8_t, std::string>{'C', "bay-C"}));

  auto refused = hub->assign_address("bay-C", std::nullopt, 'A');
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code, Errc::out_of_range);
  EXPECT_NE(refused.error().message.find("'A' is already in use"), std::string::npos) << refused.error().message;

  auto moved = hub->assign_address("bay-C", std::nullopt, 'E');
  ASSERT_TRUE(moved.ok()) << moved.error().message;
  scan = hub->scan_bus("bay-A");
  ASSERT_TRUE(scan.ok()) << scan.error().message;
  EXPECT_EQ(addresses(*scan), "ABDE");
  auto back = hub->assign_address("bay-C", std::uint8_t{'E'}, 'C');
  ASSERT_TRUE(back.ok()) << back.error().message;  // assign checks the unit answers at C again

  EXPECT_EQ(hub->scan_bus("silo").error().code, Errc::unsupported);
  EXPECT_EQ(hub->assign_address("belt", std::nullopt, 'E').error().code, Errc::unsupported);
}

// U110: §2 Continuous Output "The continuous output data rate is the pulses per measure
// divided by the PRF", and a poll faster than that returns a measurement twice (U89). The
// network poll (§7 "The ULS Interface Program periodically polls the units") asks each unit
// again one output period after its previous answer: bay-A at PRF 4000 Hz and 400 pulses per
// measure (100 ms) gives samples at least 100 ms apart (it was polled about 27 times a second).
// Look down is reported by its changes (U87): bay-B, with nothing passing, gives one sample.
TEST(HubPty, U110_TheBusPollsEachUnitOncePerOutputPeriod) {
  Site site;
  auto hub = Hub::start(site.config);
  auto averaging =
      hub->set("bay-A", {{"mode", "averaging"}, {"averaging-weight", "100"}, {"prf-hz", "4000"}, {"ppm", "400"}});
  ASSERT_TRUE(averaging.ok()) << averaging.error().message;
  auto look_down = hub->set("bay-B", {{"mode", "look-down"}});
  ASSERT_TRUE(look_down.ok()) << look_down.error().message;
  auto bay_a = hub->subscribe("bay-A", 1000, OverflowPolicy::drop_oldest);
  auto bay_b = hub->subscribe("bay-B", 1000, OverflowPolicy::drop_oldest);
  ASSERT_TRUE(bay_a.ok() && bay_b.ok());
  std::vector<Sample> samples;
  ASSERT_TRUE(take_until(**bay_a, [&](const HubItem& item) {
    if (const auto* sample = std::get_if<Sample>(&item.item)) samples.push_back(*sample);
    return samples.size() >= 8;
  }));
  for (std::size_t i = 1; i < samples.size(); ++i) {
    EXPECT_GE(samples[i].time - samples[i - 1].time, 100ms) << "samples " << i - 1 << " and " << i;
  }
  // 700 ms and more have passed: at 50 ms a poll, more than ten look-down answers, all OFF.
  std::size_t look_down_samples = 0;
  for (const HubItemPtr& item : (*bay_b)->take(1000, 0ms)) {
    if (std::holds_alternative<Sample>(item->item)) ++look_down_samples;
  }
  EXPECT_EQ(look_down_samples, 1u);
}

namespace {

// A bus whose site file names a unit that is not there (C): the scan hears A, B and D only.
// Each answer belongs to the sensor at its own address: D's is not given to bay-C, bay-C is
// reported silent, and bay-D is served as D.
TEST(HubPty, AUnitMissingFromTheBusIsReportedAndTheOthersKeepTheirOwnAddresses) {
  TempDir temp;
  const std::string port = (temp.path / "bus").string();
  Child bus{{"sim", "uls", "--bus", port, "--address", "A", "--address", "B", "--address", "D"}};
  ASSERT_TRUE(ready(bus));
  std::string site;
  for (const char* unit : {"A", "B", "D"}) {
    const auto run =
        ls5_driver_test::run_cli(temp.path, {"uls", "set", "--port", port, "--address", unit, "continuous=off"});  // §7
    ASSERT_EQ(run.exit_code, 0) << run.err;
  }
  for (const char* unit : {"A", "B", "C", "D"}) {
    site += "[[sensor]]\nname = \"bay-" + std::string(unit) + "\"\nfamily = \"uls\"\nport = \"" + port +
            "\"\naddress = \"" + unit + "\"\n";
  }
  auto config = parse_site_config(site, "site.toml");
  ASSERT_TRUE(config.ok()) << config.error().message;
  auto hub = Hub::start(*config);
  auto all = hub->subscribe("", 100000, OverflowPolicy::drop_oldest);
  ASSERT_TRUE(all.ok());
  // The scan may be over before the subscription: what it said is read from the ring.
  const auto said_to_bay_c = [&] {
    const auto ring = hub->since("bay-C", 0);
    if (!ring) return std::string();
    for (const HubItemPtr& item : ring->items) {
      const auto* event = std::get_if<StreamEvent>(&item->item);
      if (event != nullptr && event->kind == StreamEventKind::disconnected) return event->message;
    }
    return std::string();
  };
  ASSERT_TRUE(take_until(**all, [&](const HubItem& /*item*/) { return !said_to_bay_c().empty(); }));
  EXPECT_EQ(said_to_bay_c().rfind("no answer at address C", 0), 0u) << said_to_bay_c();
  ASSERT_TRUE(take_until(
      **all, [](const HubItem& item) { return item.sensor == "bay-D" && std::holds_alternative<Sample>(item.item); }));
  EXPECT_EQ(value_of(hub->sensor("bay-D")->identity, "address"), "D");
  EXPECT_EQ(value_of(hub->sensor("bay-B")->identity, "address"), "B");
  EXPECT_FALSE(hub->sensor("bay-C")->health.connected);
}

// U123: §2 "Laser On: The laser is firing."; §8 Get Unit Status "n = 7 = laser firing and
// Averaging Mode", "n = 1 = unit ready, not measuring". The status follows a streaming unit.
TEST(HubPty, U123_TheStatusOfAStreamingUnitSaysTheLaserFires) {
  Site site;
  auto hub = Hub::start(site.config);
  auto silo = hub->subscribe("silo", 1000, OverflowPolicy::drop_oldest);
  ASSERT_TRUE(silo.ok());
  ASSERT_TRUE(take_until(**silo, [](const HubItem& item) { return std::holds_alternative<Sample>(item.item); }));
  // Set by the worker as the stream started, before it published any sample.
  auto firing = hub->sensor("silo")->status;
  EXPECT_EQ(value_of(firing, "laser-firing"), "yes");
  EXPECT_EQ(value_of(firing, "status"), "7");
  EXPECT_EQ(value_of(firing, "averaging"), "yes");
  ASSERT_TRUE(hub->act("silo", "stop").ok());
  auto idle = hub->sensor("silo")->status;  // read again when the stream ended (ST sent)
  EXPECT_EQ(value_of(idle, "laser-firing"), "no");
  EXPECT_EQ(value_of(idle, "status"), "1");
  ASSERT_TRUE(hub->act("silo", "start").ok());
  EXPECT_EQ(value_of(hub->sensor("silo")->status, "status"), "7");
}

}  // namespace
