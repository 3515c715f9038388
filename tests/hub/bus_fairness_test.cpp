// Commands to units of an RS-485 bus polled at the wire's limit (four emulated ULS units each
// measuring every 2 ms, so a unit is always due): each command is answered within one poll
// cycle (at most one poll per unit between its posting and its answer), clients that command
// without pause do not stop the poll, and neither does a bus scan. Counted by the hub's own
// sequence numbers (a poll publishes one sample), not timed (U134).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <map>
#include <mutex>
#include <thread>

#include "ls5_driver/cli_process.hpp"
#include "rangekit/hub/hub.hpp"
#include "rangekit/hub/site_config.hpp"

namespace {

using namespace rangekit;
using namespace rangekit::hub;
using namespace std::chrono_literals;
using ls5_driver_test::Child;
using ls5_driver_test::TempDir;

constexpr std::array<const char*, 4> units{"A", "B", "C", "D"};

struct FastBus {
  TempDir temp;
  std::string port = (temp.path / "bus").string();
  Child bus{{"sim", "uls", "--bus", port, "--address", "A", "--address", "B", "--address", "C", "--address", "D"}};
  SiteConfig config;
  FastBus() {
    EXPECT_NE(bus.read_line().find("ready"), std::string::npos);
    std::string site;
    for (const char* unit : units) {
      // §7: Continuous Output off on a bus. A reading every 2 ms (PPM 10 at PRF 5000, AW below PPM).
      const auto run =
          ls5_driver_test::run_cli(temp.path, {"uls", "set", "--port", port, "--address", unit, "continuous=off",
                                               "averaging-weight=8", "ppm=10", "prf-hz=5000"});
      EXPECT_EQ(run.exit_code, 0) << run.err;
      site += "[[sensor]]\nname = \"bay-" + std::string(unit) + "\"\nfamily = \"uls\"\nport = \"" + port +
              "\"\naddress = \"" + unit + "\"\n";
    }
    auto parsed = parse_site_config(site, "site.toml");
    EXPECT_TRUE(parsed.ok()) << (parsed.ok() ? "" : parsed.error().message);
    if (parsed) config = *parsed;
  }
};

// Every sample the hub published, by sequence number: one per unit poll.
class PollLog {
 public:
  explicit PollLog(Hub& hub) : subscription_(*hub.subscribe("", 1'000'000, OverflowPolicy::drop_oldest)) {}
  // Takes what has been published up to `last` (a number the hub gave after this log began).
  void catch_up(std::uint64_t last) {
    const auto deadline = std::chrono::steady_clock::now() + 60s;  // a safety net, not a wait
    while (newest_ < last && std::chrono::steady_clock::now() < deadline) take();
  }
  // Takes until every unit of the bus has been polled once.
  bool every_unit_polled(std::size_t count) {
    const auto deadline = std::chrono::steady_clock::now() + 60s;  // a safety net, not a wait
    while (per_unit(0, newest_).size() < count && std::chrono::steady_clock::now() < deadline) take();
    return per_unit(0, newest_).size() == count;
  }
  // Polls with a number in (after, upto].
  [[nodiscard]] std::size_t between(std::uint64_t after, std::uint64_t upto) const {
    return static_cast<std::size_t>(std::count_if(
        polls_.begin(), polls_.end(), [&](const auto& poll) { return poll.first > after && poll.first <= upto; }));
  }
  [[nodiscard]] std::map<std::string, std::size_t> per_unit(std::uint64_t after, std::uint64_t upto) const {
    std::map<std::string, std::size_t> counts;
    for (const auto& [sequence, sensor] : polls_) {
      if (sequence > after && sequence <= upto) ++counts[sensor];
    }
    return counts;
  }

 private:
  void take() {
    for (const HubItemPtr& item : subscription_->take(4096, 200ms)) {
      newest_ = std::max(newest_, item->sequence);
      if (std::holds_alternative<Sample>(item->item)) polls_.emplace_back(item->sequence, item->sensor);
    }
  }
  SubscriptionPtr subscription_;
  std::uint64_t newest_ = 0;
  std::vector<std::pair<std::uint64_t, std::string>> polls_;
};

// The hub's numbers just before a command was posted and just after it was answered.
struct Span {
  std::uint64_t posted = 0;
  std::uint64_t answered = 0;
};

// Two clients, each at its own unit, every setting (`read`: some thirty requests) and a single
// measurement in turn, each asking again as soon as it is answered.
TEST(BusFairness, U134_CommandsAreAnsweredWithinOnePollCycleAndDoNotStopThePoll) {
  FastBus site;
  auto hub = Hub::start(site.config);
  PollLog log(*hub);
  ASSERT_TRUE(log.every_unit_polled(units.size()));  // polled at full speed first
  constexpr int rounds = 6;
  std::mutex mutex;
  std::vector<Span> spans;
  std::atomic<int> failed{0};
  std::vector<std::thread> clients;
  for (const char* unit : {"bay-A", "bay-C"}) {
    clients.emplace_back([&, unit] {
      for (int turn = 0; turn < 2 * rounds; ++turn) {
        Span span;
        span.posted = hub->last_sequence();
        const auto answer = hub->act(unit, turn % 2 == 0 ? "read" : "single");
        span.answered = hub->last_sequence();
        if (!answer) ++failed;
        const std::lock_guard lock(mutex);
        spans.push_back(span);
      }
    });
  }
  for (auto& client : clients) client.join();
  EXPECT_EQ(failed, 0);
  const auto first = std::min_element(spans.begin(), spans.end(), [](const Span& a, const Span& b) {
                       return a.answered < b.answered;
                     })->answered;
  const auto last = std::max_element(spans.begin(), spans.end(), [](const Span& a, const Span& b) {
                      return a.answered < b.answered;
                    })->answered;
  log.catch_up(last);
  for (const Span& span : spans) {
    EXPECT_LE(log.between(span.posted, span.answered), units.size())
        << "polls between sequence " << span.posted << " and " << span.answered;
  }
  // The poll went on while the clients commanded: every unit had its turn, more than once.
  const auto polled = log.per_unit(first, last);
  for (const char* unit : units) {
    const auto at = polled.find("bay-" + std::string(unit));
    EXPECT_TRUE(at != polled.end() && at->second >= 2)
        << "bay-" << unit << " polled " << (at == polled.end() ? 0 : at->second) << " times";
  }
}

// A scan of every address (58 of them silent, 200 ms each) with a client commanding beside it:
// the poll and the commands go on between two addresses asked, not only between two jobs.
TEST(BusFairness, U105_U134_AScanDoesNotStopThePollNorTheCommands) {
  FastBus site;
  auto hub = Hub::start(site.config);
  PollLog log(*hub);
  ASSERT_TRUE(log.every_unit_polled(units.size()));
  std::atomic<bool> scanning{true};
  Result<BusScan> scan = make_error(Errc::timeout, "not run");
  std::uint64_t scan_started = hub->last_sequence();
  std::thread scanner([&] {
    scan = hub->scan_bus("bay-A");
    scanning = false;
  });
  std::vector<Span> spans;
  while (scanning) {
    Span span;
    span.posted = hub->last_sequence();
    const auto answer = hub->act("bay-B", "single");
    span.answered = hub->last_sequence();
    EXPECT_TRUE(answer.ok()) << answer.error().message;
    if (scanning) spans.push_back(span);
  }
  scanner.join();
  const std::uint64_t scan_ended = hub->last_sequence();
  ASSERT_TRUE(scan.ok()) << scan.error().message;
  EXPECT_EQ(scan->found.size(), units.size());
  log.catch_up(scan_ended);
  // One poll at least after each address asked (a unit is due again every 5 ms): before, the
  // poll ran only between two jobs of eight addresses.
  EXPECT_GE(log.between(scan_started, scan_ended), scan->asked - units.size());
  // A command posted during the scan waits for the address being asked, not for eight of them.
  EXPECT_GE(spans.size(), scan->asked / 2);
  for (const Span& span : spans) {
    EXPECT_LE(log.between(span.posted, span.answered), units.size())
        << "polls between sequence " << span.posted << " and " << span.answered;
  }
}

}  // namespace
