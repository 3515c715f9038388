// [mqtt] spool against a real mosquitto: QoS 1 readings wait on disk through a broker outage
// and a restart of the bridge, and arrive afterwards, each sensor's seq complete; the broker
// keeps the subscriber's session (persistence on), so it hears all the broker acknowledged.
#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <set>

#include "mqtt/bridge_rig.hpp"
#include "mqtt/reading_spool.hpp"
#include "rangekit/record/spool.hpp"

namespace {

using namespace rangekit;
using namespace std::chrono_literals;
using mqtt_test::Heard;

// The seqs of the readings heard, each once.
std::set<std::uint64_t> seqs_heard(const std::vector<Heard>& heard) {
  std::set<std::uint64_t> seqs;
  for (const auto& payload : mqtt_test::payloads_on(heard, "rangekit/belt/reading")) {
    if (payload.is_object() && payload.contains("seq")) seqs.insert(payload["seq"].get<std::uint64_t>());
  }
  return seqs;
}

TEST(MqttSpool, ABrokerOutageAndARestartLoseNoReadingAndEachArrivesWithItsSeq) {
  mqtt_test::TempDir state;
  mqtt_test::TempDir broker_dir;
  mqtt_test::Broker broker(
      {}, {}, "persistence true\npersistence_location " + broker_dir.path.string() + "/\nmax_queued_messages 0\n");
  mqtt_test::Ls5 ls5;
  auto hub = hub::Hub::start(ls5.site);
  mqtt_test::Subscriber subscriber(broker.port(), {"rangekit/belt/reading"},
                                   "rangekit-spool-test-" + std::to_string(::getpid()));
  ASSERT_TRUE(subscriber.wait_subscribed());
  auto options = mqtt_test::options_for(broker, 0);  // every sample
  options.config.qos_reading = 1;
  options.config.spool = true;
  options.config.reconnect_max_s = 1;
  options.config.queue_limit = 5;  // the memory queue would drop nearly all of the outage
  options.spool_dir = (state.path / "spool").string();
  auto bridge = mqtt::Bridge::start(*hub, options);
  ASSERT_TRUE(bridge.ok()) << bridge.error().message;
  ASSERT_TRUE(subscriber.wait_for([](const auto& heard) { return seqs_heard(heard).size() >= 20; }));

  broker.broker->stop();  // SIGTERM: the broker saves the subscriber's session
  ASSERT_TRUE(mqtt_test::until([&] { return (*bridge)->stats().spooled >= 200; }))
      << "readings did not wait on disk while the broker was away";
  (*bridge)->stop();  // the service ends with the readings on disk
  ASSERT_TRUE(broker.broker->restart().ok());
  bridge = mqtt::Bridge::start(*hub, options);  // the next start sends them first
  ASSERT_TRUE(bridge.ok()) << bridge.error().message;
  ASSERT_TRUE(mqtt_test::until([&] { return (*bridge)->stats().connected; }));
  hub->stop();  // no new readings: the spool can empty
  ASSERT_TRUE(mqtt_test::until([&] { return (*bridge)->stats().spooled == 0; }))
      << (*bridge)->stats().spooled << " readings still wait";
  (*bridge)->stop();

  // The last seq the bridge gave, as its spool keeps it for the next start.
  auto spool = record::Spool::open((state.path / "spool" / mqtt::reading_spool_name("rangekit", "belt")).string(), 1);
  ASSERT_TRUE(spool.ok());
  const std::uint64_t last = (*spool)->next_seq("belt") - 1;
  ASSERT_GT(last, 200u);
  ASSERT_TRUE(subscriber.wait_for([&](const auto& heard) { return seqs_heard(heard).size() == last; }))
      << "heard " << seqs_heard(subscriber.heard()).size() << " of " << last << " readings";
  const auto seqs = seqs_heard(subscriber.heard());
  EXPECT_EQ(*seqs.begin(), 1u);
  EXPECT_EQ(*seqs.rbegin(), last);  // 1..last, each once: no gap
  EXPECT_EQ((*bridge)->stats().dropped, 0u);
}

}  // namespace
