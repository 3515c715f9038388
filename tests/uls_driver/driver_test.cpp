// The ULS driver against scripted device bytes on the in-memory loopback pair:
// reply matching, local validation, device errors, timeouts and retries,
// malformed and half frames, the stream and reconnect (docs/host-uls.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>

#include "rangekit/uls/bus.hpp"
#include "rangekit/uls/driver.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/family.hpp"
#include "uls_driver/scripted_device.hpp"

namespace rangekit::uls {
namespace {

using namespace std::chrono_literals;
using testing::ScriptedDevice;

// A small settings table answering gets like a unit in averaging, metres (§8).
std::string typical_reply(const std::string& request) {
  static const std::map<std::string, std::string> gets{{"$MM", "$MM,1\r"},        {"$DM", "$DM,2\r"},
                                                       {"$MU", "$MU,1\r"},        {"$TB", "$TB,0\r"},
                                                       {"$CO", "$CO,1\r"},        {"$PF", "$PF,2000,2000,2000\r"},
                                                       {"$PO", "$PO,100,1024\r"}, {"$ID", "$ID,ULS 1.0,2026\r"},
                                                       {"$US", "$US,1\r"}};  // ready, not measuring
  if (auto found = gets.find(request); found != gets.end()) return found->second;
  if (request == "$GO" || request == "$ST") return "$OK\r";
  return "";
}

struct Rig {
  std::unique_ptr<Driver> driver;
  std::unique_ptr<ScriptedDevice> device;
  explicit Rig(ScriptedDevice::Handler handler, DriverOptions options = {}, ReopenFunction reopen = {}) {
    auto pair = make_loopback_pair("host", "device");
    options.timeout = options.timeout == 1000ms ? 300ms : options.timeout;
    driver = std::make_unique<Driver>(std::move(pair.a), options, std::move(reopen));
    device = std::make_unique<ScriptedDevice>(std::move(pair.b), std::move(handler));
  }
};

TEST(UlsDriver, GetSkipsMeasurementLinesThatArriveBeforeTheReply) {
  Rig rig([](const std::string& request) -> std::string {
    if (request == "$MM") return "$BM,12.345,1000\r$MM,2\r";
    return "";
  });
  auto mode = rig.driver->mode();
  ASSERT_TRUE(mode) << mode.error().message;
  EXPECT_EQ(*mode, Mode::binning);
  // Not a reply: handed to the measurement path, which has not read MM/DM/MU/TB yet and so
  // does not decode it with a guess (U85): neither a measurement nor a bad frame.
  const auto counters = rig.driver->counters();
  EXPECT_EQ(counters.undecoded, 1U);
  EXPECT_EQ(counters.measurements, 0U);
  EXPECT_EQ(counters.bad_frames, 0U);
  EXPECT_EQ(counters.replies, 1U);
}

TEST(UlsDriver, ValuesOutsideTheTableAreRefusedBeforeAnythingIsSent) {
  Rig rig([](const std::string&) { return std::string("$OK\r"); });
  auto prf = rig.driver->set_prf(6000);
  ASSERT_FALSE(prf);
  EXPECT_EQ(prf.error().code, Errc::out_of_range);
  EXPECT_NE(prf.error().message.find("10..5000"), std::string::npos) << prf.error().message;
  EXPECT_NE(prf.error().message.find("32"), std::string::npos) << prf.error().message;  // the unit's error number
  auto weight = rig.driver->set("AW", "0");
  ASSERT_FALSE(weight);
  EXPECT_EQ(weight.error().code, Errc::out_of_range);
  auto unknown = rig.driver->set("QQ", "1");
  ASSERT_FALSE(unknown);
  EXPECT_EQ(unknown.error().code, Errc::unknown_command);
  auto get_only = rig.driver->set("US", "1");
  ASSERT_FALSE(get_only);
  EXPECT_EQ(get_only.error().code, Errc::wrong_form);
  auto set_only = rig.driver->get("PT");
  ASSERT_FALSE(set_only);
  EXPECT_EQ(set_only.error().code, Errc::wrong_form);
  // Then a valid set goes out: the device saw exactly that one.
  ASSERT_TRUE(rig.driver->set_prf(2000));
  ASSERT_TRUE(rig.device->wait_for_requests(1));
  EXPECT_EQ(rig.device->requests(), std::vector<std::string>{"$PF,2000"});
}

TEST(UlsDriver, DeviceErrorsCarryTheNumberAndTheSection10Text) {
  Rig rig([](const std::string& request) -> std::string {
    if (request == "$MM,2") return "$ER,31\r";
    return "";
  });
  auto set = rig.driver->set_mode(Mode::binning);
  ASSERT_FALSE(set);
  EXPECT_EQ(set.error().code, Errc::device_error);
  EXPECT_EQ(set.error().device_code, 31);
  EXPECT_NE(set.error().message.find(std::string(find_error(31)->explanation)), std::string::npos)
      << set.error().message;
}

// U91: §9 "Baud Rate Choices" 1200 2400 4800 9600 14400 19200 38400 57600 115200, 230400
// (command); §10 34 Invalid Baud Rate. A refused baud names the bauds, not the ports, and a
// lone value is not taken for a port.
TEST(UlsDriver, U91_ARefusedBaudNamesTheAllowedBauds) {
  Rig rig([](const std::string&) { return std::string("$OK\r"); });
  auto set = rig.driver->set_baud(BaudPort::configuration, 28800);
  ASSERT_FALSE(set);
  EXPECT_EQ(set.error().code, Errc::out_of_range);
  const std::string& message = set.error().message;
  EXPECT_NE(message.find("1200, 2400, 4800, 9600, 14400, 19200, 38400, 57600, 115200, 230400"), std::string::npos)
      << message;
  EXPECT_NE(message.find("error 34, Invalid Baud Rate"), std::string::npos) << message;
  EXPECT_EQ(message.find("output port"), std::string::npos) << message;

  const std::array<std::string_view, 1> lone{"28800"};
  auto alone = rig.driver->set("BR", lone);
  ASSERT_FALSE(alone);
  EXPECT_NE(alone.error().message.find("the port and the baud"), std::string::npos) << alone.error().message;
  EXPECT_NE(alone.error().message.find("115200"), std::string::npos) << alone.error().message;
  EXPECT_EQ(alone.error().message.find("Invalid Port"), std::string::npos) << alone.error().message;

  const std::array<std::string_view, 2> bad_port{"3", "9600"};
  auto port = rig.driver->set("BR", bad_port);
  ASSERT_FALSE(port);
  EXPECT_NE(port.error().message.find("0 configuration port, 1 output port"), std::string::npos)
      << port.error().message;
  EXPECT_TRUE(rig.device->requests().empty());  // all refused before sending
}

TEST(UlsDriver, StreamErrorsAreNotTakenForTheReplyOfASet) {
  // docs/conformance.md U60: $ER,4 and $ER,5 are measurement errors (U13), never an answer.
  Rig rig([](const std::string& request) -> std::string {
    if (request == "$PL,1") return "$ER,4\r$ER,5\r$OK\r";
    return "";
  });
  ASSERT_TRUE(rig.driver->set_power(PowerLevel::medium));
  // Taken as measurement lines (not decoded: no MM/DM/MU/TB read yet, U85).
  EXPECT_EQ(rig.driver->counters().undecoded, 2U);
}

TEST(UlsDriver, NoReplyTimesOutAndGetsAreSentTwice) {
  Rig rig([](const std::string&) { return std::string(); });
  auto mode = rig.driver->mode();
  ASSERT_FALSE(mode);
  EXPECT_EQ(mode.error().code, Errc::timeout);
  EXPECT_NE(mode.error().message.find("baud"), std::string::npos) << mode.error().message;
  ASSERT_TRUE(rig.device->wait_for_requests(2));
  EXPECT_EQ(rig.device->requests(), (std::vector<std::string>{"$MM", "$MM"}));
  auto set = rig.driver->set_mode(Mode::averaging);
  ASSERT_FALSE(set);
  EXPECT_EQ(set.error().code, Errc::timeout);
  EXPECT_EQ(rig.device->requests().size(), 3U);  // sets are not repeated
  EXPECT_EQ(rig.driver->counters().retries, 1U);
}

TEST(UlsDriver, RetryAnswersWhenTheFirstReplyWasLost) {
  int asked = 0;
  Rig rig([&](const std::string& request) -> std::string {
    if (request != "$US") return "";
    return ++asked == 1 ? "" : "$US,11\r";
  });
  auto status = rig.driver->status();
  ASSERT_TRUE(status) << status.error().message;
  EXPECT_TRUE(status->binning_calc);
  EXPECT_TRUE(status->laser_firing);
  EXPECT_EQ(status->mode, Mode::binning);
}

TEST(UlsDriver, HalfFramesAreJoined) {
  ScriptedDevice* device = nullptr;
  Rig rig([&](const std::string& request) -> std::string {
    if (request == "$MU") {
      device->send("$M");
      device->send("U,");
      return "0\r";
    }
    return "";
  });
  device = rig.device.get();
  auto units = rig.driver->units();
  ASSERT_TRUE(units) << units.error().message;
  EXPECT_EQ(*units, Units::feet);
}

// Every framer rejection of the codec's corpus (tests/uls/malformed_test.cpp)
// before the reply: the bad bytes are counted, the reply still matches.
TEST(UlsDriver, MalformedBytesBeforeTheReplyAreCountedAndSkipped) {
  const std::vector<std::string> corpus{"#\r",
                                        "$\r",
                                        "#Z\r",
                                        "$,1\r",
                                        "$MM,1\n",
                                        "$MM,1\n\r",
                                        "$MM,\x7F\r",
                                        "$MM,\xC0\r",
                                        "#/MM,1\r",
                                        "#\x01MM,1\r",
                                        "#,MM\r",
                                        "$M\r",
                                        "$MMMMM,1\r",
                                        "$M1,1\r",
                                        "$M M\r",
                                        "$MM,\r",
                                        "$BR,,9600\r",
                                        "$PF,1,2,\r",
                                        "$BM,1,2,3,4,5,6,7,8,9\r",
                                        "$0BG8\r",
                                        "$0bb8\r",
                                        "$00\r",
                                        "#Z12345\r",
                                        "xx",
                                        "$BM,1.2$BM,1.3\r",
                                        "$BM,abc.def,5\r",
                                        "$BM,0,0,1.000,5\r"};
  for (const auto& garbage : corpus) {
    Rig rig([&](const std::string& request) -> std::string {
      if (request == "$DM") return garbage + "$DM,3\r";
      return "";
    });
    auto display = rig.driver->display_mode();
    ASSERT_TRUE(display) << "after '" << garbage << "': " << display.error().message;
    EXPECT_EQ(*display, DisplayMode::intensity) << garbage;
    const auto counters = rig.driver->counters();
    EXPECT_GE(counters.bad_frames + counters.measurements + counters.unexpected + counters.undecoded, 1U) << garbage;
  }
}

TEST(UlsDriver, AReplyWithTheWrongShapeIsAnErrorNotACrash) {
  Rig rig([](const std::string& request) -> std::string {
    if (request == "$PF") return "$PF,1000,1000\r";
    if (request == "$MM") return "$MM\r";
    return "";
  });
  auto prf = rig.driver->prf();
  ASSERT_FALSE(prf);
  EXPECT_EQ(prf.error().code, Errc::invalid_frame);
  auto mode = rig.driver->mode();
  ASSERT_FALSE(mode);
}

TEST(UlsDriver, AddressedProtocolFramesAndMatchesByAddress) {
  DriverOptions options;
  options.address = 'A';
  Rig rig(
      [](const std::string& request) -> std::string {
        // Another unit's reply first (must not be taken), then ours.
        if (request == "#AMM") return "#BMM,3\r#AMM,2\r";
        if (request == "#AMM,3") return "#AOK\r";
        return "";
      },
      options);
  auto mode = rig.driver->mode();
  ASSERT_TRUE(mode) << mode.error().message;
  EXPECT_EQ(*mode, Mode::binning);
  EXPECT_TRUE(rig.driver->set_mode(Mode::look_down));
  EXPECT_EQ(rig.driver->counters().other_units, 1U);
  EXPECT_EQ(rig.driver->counters().unexpected, 0U);
}

// A unit asked before that answers late, while the scan asks the next address, is not a unit
// there and no collision (§8: a reply names its unit, "#aCCCC").
TEST(UlsBus, ALateReplyFromAnotherAddressIsNeitherAUnitNorACollision) {
  auto pair = make_loopback_pair("host", "device");
  BusOptions options;
  options.timeout = 300ms;
  Bus bus(std::move(pair.a), options);
  ScriptedDevice device(std::move(pair.b), [](const std::string& request) -> std::string {
    if (request == "#AID") return "#AID,ULS 1.0,2026\r";
    if (request == "#AUS") return "#AUS,1\r";
    if (request == "#BID") return "#AUS,1\r";  // A again, late; B is silent
    if (request == "#CID") return "#CID,ULS 1.0,2026\r";
    if (request == "#CUS") return "#CUS,1\r";
    return "";
  });
  const auto found = bus.scan({'A', 'B', 'C'});
  ASSERT_EQ(found.size(), 2U);
  EXPECT_EQ(found[0].address, 'A');
  EXPECT_FALSE(found[0].duplicate);
  EXPECT_EQ(found[1].address, 'C');
  EXPECT_FALSE(found[1].duplicate);
  EXPECT_GE(bus.driver().counters().other_units, 1U);
}

TEST(UlsDriver, DistancesAreMetresWhateverTheUnitsSetting) {
  Rig rig([](const std::string& request) -> std::string {
    if (request == "$MU") return "$MU,0\r";      // feet
    if (request == "$SG") return "$SG,10.00\r";  // 10 ft
    if (request == "$SG,32.81") return "$OK\r";  // 10 m in feet, 2 decimals (§9)
    return "";
  });
  auto gate = rig.driver->short_gate_m();
  ASSERT_TRUE(gate) << gate.error().message;
  EXPECT_NEAR(*gate, 3.048, 1e-9);
  ASSERT_TRUE(rig.driver->set_short_gate_m(10.0));
  // 1700 m is the top of the range in any units: 1701 m is refused locally in feet too.
  auto far = rig.driver->set_short_gate_m(1701.0);
  ASSERT_FALSE(far);
  EXPECT_EQ(far.error().code, Errc::out_of_range);
  EXPECT_NE(far.error().message.find("feet"), std::string::npos) << far.error().message;
}

TEST(UlsDriver, MeasureCollectsAWholeBinningArray) {
  Rig rig([](const std::string& request) -> std::string {
    if (request == "$MM") return "$MM,2\r";
    if (request == "$BM") return "$BM,0,2,10.000,300\r$BM,1,2,25.500,40\r";
    return typical_reply(request);
  });
  auto sample = rig.driver->measure();
  ASSERT_TRUE(sample) << sample.error().message;
  EXPECT_EQ(sample->kind, uls::kind::binning);
  ASSERT_EQ(sample->targets.size(), 2U);
  EXPECT_DOUBLE_EQ(sample->targets[1].distance_m, 25.5);
  EXPECT_EQ(sample->targets[0].strength, 300U);
  EXPECT_EQ(sample->device, "uls");
}

// A bus poll measures each unit in turn: the settings a BM line reads by (MM, DM, MU, TB)
// are read from each unit once, kept across set_address, and read again after a set of one.
TEST(UlsDriver, MeasureReadsEachUnitsSettingsOnceUntilASetChangesThem) {
  std::mutex mutex;
  std::map<std::string, int> asked;
  Rig rig([&](const std::string& request) -> std::string {
    {
      const std::lock_guard lock(mutex);
      ++asked[request];
    }
    if (request.size() < 3 || request[0] != '#') return "";
    const std::string unit = request.substr(0, 2);  // "#A"
    const std::string mnemonic = request.substr(2);
    if (mnemonic == "BM") return unit + "BM,7.000,12345\r";
    if (mnemonic == "MU,0") return unit + "OK\r";
    const std::string reply = typical_reply("$" + mnemonic);
    return reply.empty() ? "" : unit + reply.substr(1);
  });
  const auto asked_for = [&](const std::string& request) {
    const std::lock_guard lock(mutex);
    return asked[request];
  };
  for (int round = 0; round < 3; ++round) {
    for (const char unit : {'A', 'B'}) {
      ASSERT_TRUE(rig.driver->set_address(static_cast<std::uint8_t>(unit)));
      auto sample = rig.driver->measure();
      ASSERT_TRUE(sample) << sample.error().message;
      EXPECT_DOUBLE_EQ(sample->get(channel::distance_m).value_or(0), 7.0);
    }
  }
  EXPECT_EQ(asked_for("#ABM"), 3);
  for (const char* setting : {"#AMM", "#ADM", "#AMU", "#ATB", "#BMM", "#BDM", "#BMU", "#BTB"}) {
    EXPECT_EQ(asked_for(setting), 1) << setting;
  }
  // A set of one of them through the driver: that unit is read again, the other is not.
  ASSERT_TRUE(rig.driver->set_address(static_cast<std::uint8_t>('A')));
  ASSERT_TRUE(rig.driver->set("MU", "0"));
  ASSERT_TRUE(rig.driver->measure());
  ASSERT_TRUE(rig.driver->set_address(static_cast<std::uint8_t>('B')));
  ASSERT_TRUE(rig.driver->measure());
  EXPECT_EQ(asked_for("#AMM"), 2);
  EXPECT_EQ(asked_for("#BMM"), 1);
}

std::vector<StreamItem> take(SampleSource& source, std::size_t samples) {
  std::vector<StreamItem> items;
  std::size_t seen = 0;
  const auto until = std::chrono::steady_clock::now() + 10s;
  while (seen < samples && std::chrono::steady_clock::now() < until) {
    auto item = source.next(100ms);
    if (!item) continue;
    if (std::holds_alternative<Sample>(*item)) ++seen;
    items.push_back(std::move(*item));
  }
  return items;
}

std::vector<Sample> samples_of(const std::vector<StreamItem>& items) {
  std::vector<Sample> samples;
  for (const auto& item : items)
    if (const auto* sample = std::get_if<Sample>(&item)) samples.push_back(*sample);
  return samples;
}

TEST(UlsDriver, StreamDecodesAveragingLinesAndErrors) {
  ScriptedDevice* device = nullptr;
  Rig rig([&](const std::string& request) -> std::string {
    if (request == "$GO") {
      device->send("$OK\r$BM,12.500,2100\r$ER,4\r$BM,13.000,2200\r");
      return "";
    }
    return typical_reply(request);
  });
  device = rig.device.get();
  auto stream = rig.driver->start_stream();
  ASSERT_TRUE(stream) << stream.error().message;
  const auto samples = samples_of(take(**stream, 3));
  ASSERT_EQ(samples.size(), 3U);
  EXPECT_EQ(samples[0].kind, uls::kind::averaging);
  EXPECT_DOUBLE_EQ(*samples[0].get(uls::channel::distance_m), 12.5);
  EXPECT_EQ(*samples[0].get(uls::channel::pulse_width_ps), 2100U);
  EXPECT_EQ(samples[1].kind, uls::kind::error);
  EXPECT_EQ(*samples[1].get(uls::channel::error), 4);
  EXPECT_DOUBLE_EQ(*samples[2].get(uls::channel::distance_m), 13.0);
  // A get while streaming: the reader hands the reply over.
  auto version = rig.driver->version();
  ASSERT_TRUE(version) << version.error().message;
  EXPECT_EQ(*version, "ULS 1.0,2026");
  rig.driver->stop_stream();
  EXPECT_EQ(rig.device->requests().back(), "$ST");
}

// read_gather: after a read that brought bytes the reader lets the next lines
// collect for read_gather before reading again, and a stop ends that wait at once.
TEST(UlsDriver, TheStreamReaderGathersAfterAReadAndAStopEndsTheGather) {
  ScriptedDevice* device = nullptr;
  DriverOptions options;
  options.read_gather = 400ms;
  Rig rig(
      [&](const std::string& request) -> std::string {
        if (request == "$GO") {
          device->send("$OK\r$BM,12.500,2100\r");
          return "";
        }
        return typical_reply(request);
      },
      options);
  device = rig.device.get();
  auto stream = rig.driver->start_stream();
  ASSERT_TRUE(stream) << stream.error().message;
  ASSERT_EQ(samples_of(take(**stream, 1)).size(), 1U);
  device->send("$BM,13.000,2200\r");
  ASSERT_EQ(samples_of(take(**stream, 1)).size(), 1U);  // the reader has just read: it gathers now
  device->send("$BM,14.000,2300\r");
  // Without the gather this line would be read and handed over at once.
  EXPECT_FALSE((*stream)->next(100ms).has_value());
  const auto third = samples_of(take(**stream, 1));
  ASSERT_EQ(third.size(), 1U);
  EXPECT_DOUBLE_EQ(*third[0].get(uls::channel::distance_m), 14.0);

  options.read_gather = 20s;  // a stop must not wait this out
  ScriptedDevice* slow_device = nullptr;
  Rig slow(
      [&](const std::string& request) -> std::string {
        if (request == "$GO") {
          slow_device->send("$OK\r");
          return "";
        }
        return typical_reply(request);
      },
      options);
  slow_device = slow.device.get();
  auto slow_stream = slow.driver->start_stream();
  ASSERT_TRUE(slow_stream) << slow_stream.error().message;
  slow_device->send("$BM,12.500,2100\r");
  ASSERT_EQ(samples_of(take(**slow_stream, 1)).size(), 1U);  // read: the reader gathers for 20 s
  const auto asked = std::chrono::steady_clock::now();
  (*slow_stream)->stop();
  EXPECT_LT(std::chrono::steady_clock::now() - asked, 10s);
}

// U85: a unit already measuring (CO on, averaging, DM 2 "range and pulse width") sends
// `$BM,n,p` lines (§8 Averaging Mode: "Output from ULS depends on selected display output
// mode: Range, Pulse Width or Both") between the replies to the stream's MM/DM/MU/TB reads.
// None may be decoded before DM is known: a guessed "range only" would call each a bad frame.
TEST(UlsDriver, U85_LinesOfAUnitAlreadyMeasuringAreNotDecodedBeforeItsSettingsAreKnown) {
  ScriptedDevice* device = nullptr;
  Rig rig([&](const std::string& request) -> std::string {
    if (request == "$GO") {
      device->send("$BM,12.400,2000\r$OK\r$BM,12.500,2100\r$BM,12.600,2200\r");
      return "";
    }
    return "$BM,12.300,1900\r" + typical_reply(request);
  });
  device = rig.device.get();
  auto stream = rig.driver->start_stream(StreamMode::continuous);
  ASSERT_TRUE(stream) << stream.error().message;
  const auto items = take(**stream, 2);
  rig.driver->stop_stream();
  ASSERT_FALSE(items.empty());
  const auto* first = std::get_if<StreamEvent>(&items.front());
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(first->kind, StreamEventKind::connected);
  for (const auto& item : items) {
    const auto* event = std::get_if<StreamEvent>(&item);
    EXPECT_TRUE(event == nullptr || event->kind != StreamEventKind::bad_frame) << event->message;
  }
  const auto samples = samples_of(items);
  ASSERT_EQ(samples.size(), 2U);
  EXPECT_EQ(*samples[0].get(uls::channel::pulse_width_ps), 2000U);  // the line before GO's $OK: settings known by then
  EXPECT_DOUBLE_EQ(*samples[1].get(uls::channel::distance_m), 12.5);
  EXPECT_EQ(rig.driver->counters().bad_frames, 0U);
  EXPECT_GE(rig.driver->counters().undecoded, 1U);  // at least the line before the $MM reply
}

// A unit that measures from GO until ST (§8 Get Unit Status: "n = 1 = unit ready, not
// measuring", "n = 7 = laser firing and Averaging Mode"), sending one averaging line on GO.
struct MeasuringUnit {
  std::atomic<bool> measuring{false};
  ScriptedDevice* device = nullptr;
  std::string answer(const std::string& request) {
    if (request == "$US") return measuring ? "$US,7\r" : "$US,1\r";
    if (request == "$GO") {
      measuring = true;
      device->send("$OK\r$BM,12.500,2100\r");
      return "";
    }
    if (request == "$ST") {
      if (!measuring) return "$ER,86\r";  // §10 86, Instrument Not Measuring
      measuring = false;
      return "$OK\r";
    }
    return typical_reply(request);
  }
};

std::size_t count_requests(ScriptedDevice& device, const std::string& request) {
  const auto requests = device.requests();
  return static_cast<std::size_t>(std::count(requests.begin(), requests.end(), request));
}

// Reads what is left; true when the stream then says it has ended.
bool drained_and_finished(SampleSource& source) {
  while (source.next(0ms)) {
  }
  return source.finished();
}

// U86: a stream that started an idle unit stops it again however it ends: the driver's
// stop_stream(), the stream's stop() (what the CLI's stream loop calls), the stream object
// destroyed, or the driver destroyed first (the stream object then reads as finished).
TEST(UlsDriver, U86_AStreamStopsTheUnitItStartedHoweverItEnds) {
  for (const char* ending : {"stop_stream", "stop", "stream destroyed", "destructor"}) {
    SCOPED_TRACE(ending);
    MeasuringUnit unit;
    Rig rig([&](const std::string& request) { return unit.answer(request); });
    unit.device = rig.device.get();
    auto stream = rig.driver->start_stream(StreamMode::continuous);
    ASSERT_TRUE(stream) << stream.error().message;
    ASSERT_EQ(samples_of(take(**stream, 1)).size(), 1U);
    EXPECT_TRUE(unit.measuring);
    if (std::string(ending) == "stop_stream") rig.driver->stop_stream();
    if (std::string(ending) == "stop") (*stream)->stop();
    if (std::string(ending) == "stream destroyed") stream->reset();
    if (std::string(ending) == "destructor") rig.driver.reset();
    EXPECT_FALSE(unit.measuring);
    EXPECT_EQ(count_requests(*rig.device, "$GO"), 1U);
    EXPECT_EQ(count_requests(*rig.device, "$ST"), 1U);
    if (*stream) {
      EXPECT_TRUE(drained_and_finished(**stream));
    }
    if (rig.driver) {
      rig.driver.reset();  // a second ending sends nothing more
      EXPECT_EQ(count_requests(*rig.device, "$ST"), 1U);
    }
    if (*stream) {
      (*stream)->stop();  // nor does the stream's own, after the driver went
      EXPECT_EQ(count_requests(*rig.device, "$ST"), 1U);
    }
  }
}

// U86: a unit found measuring (§2 ULS Autostart "the unit will automatically start measuring
// when powered up"; a 4-20 mA loop or a trip line may feed a PLC) is neither restarted with GO
// nor stopped: the stream reads it and leaves it as it was. ST only when asked for.
TEST(UlsDriver, U86_AUnitFoundMeasuringIsLeftMeasuring) {
  for (const char* ending : {"stop_stream", "stream destroyed", "destructor", "stop_measuring"}) {
    SCOPED_TRACE(ending);
    MeasuringUnit unit;
    unit.measuring = true;
    Rig rig([&](const std::string& request) { return unit.answer(request); });
    unit.device = rig.device.get();
    auto stream = rig.driver->start_stream(StreamMode::continuous);
    ASSERT_TRUE(stream) << stream.error().message;
    rig.device->send("$BM,13.000,2200\r");
    const auto samples = samples_of(take(**stream, 1));
    ASSERT_EQ(samples.size(), 1U);
    EXPECT_DOUBLE_EQ(*samples[0].get(uls::channel::distance_m), 13.0);
    if (std::string(ending) == "stop_stream") rig.driver->stop_stream();
    if (std::string(ending) == "stream destroyed") stream->reset();
    if (std::string(ending) == "destructor") rig.driver.reset();
    if (std::string(ending) == "stop_measuring") {
      rig.driver->stop_stream(AfterStream::stop_measuring);
      EXPECT_FALSE(unit.measuring);
      EXPECT_EQ(count_requests(*rig.device, "$ST"), 1U);
      continue;
    }
    EXPECT_TRUE(unit.measuring);
    EXPECT_EQ(count_requests(*rig.device, "$GO"), 0U);
    EXPECT_EQ(count_requests(*rig.device, "$ST"), 0U);
  }
}

TEST(UlsDriver, StreamMakesOneSamplePerBinningArrayAndReadsLookDown) {
  ScriptedDevice* device = nullptr;
  std::string mode = "$MM,2\r";
  Rig rig([&](const std::string& request) -> std::string {
    if (request == "$MM") return mode;
    if (request == "$TB") return mode == "$MM,3\r" ? "$TB,1\r" : "$TB,0\r";
    if (request == "$GO") {
      device->send(mode == "$MM,2\r" ? "$OK\r$BM,0,3,1.000,9\r$BM,1,3,2.000,8\r$BM,2,3,3.000,7\r$BM,0,1,4.000,6\r"
                                     : "$OK\r$0\r$0BB8\r$0000\r");
      return "";
    }
    return typical_reply(request);
  });
  device = rig.device.get();
  auto stream = rig.driver->start_stream(StreamMode::continuous);
  ASSERT_TRUE(stream) << stream.error().message;
  auto samples = samples_of(take(**stream, 2));
  ASSERT_EQ(samples.size(), 2U);
  ASSERT_EQ(samples[0].targets.size(), 3U);
  EXPECT_DOUBLE_EQ(samples[0].targets[2].distance_m, 3.0);
  ASSERT_EQ(samples[1].targets.size(), 1U);
  rig.driver->stop_stream();

  // Look down with time between events (§8, U12): $0 no presence, $0BB8 = 3000 pulses, $0000 overflow.
  mode = "$MM,3\r";
  stream = rig.driver->start_stream(StreamMode::continuous);
  ASSERT_TRUE(stream) << stream.error().message;
  samples = samples_of(take(**stream, 3));
  ASSERT_EQ(samples.size(), 3U);
  EXPECT_EQ(samples[0].get(uls::channel::presence), false);
  EXPECT_EQ(samples[1].get(uls::channel::presence), true);
  EXPECT_EQ(samples[1].get(uls::channel::pulses_between_events), 3000U);
  // docs/conformance.md U61/U88: $0000 is more than 65535 pulses, not 0.
  EXPECT_EQ(samples[2].get(uls::channel::presence), true);
  EXPECT_TRUE(samples[2].get(uls::channel::pulses_overflow).value_or(false));
  EXPECT_FALSE(samples[2].get(uls::channel::pulses_between_events).has_value());
  rig.driver->stop_stream();
}

TEST(UlsDriver, PolledStreamAsksWithBm) {
  int polls = 0;
  Rig rig([&](const std::string& request) -> std::string {
    if (request == "$CO") return "$CO,0\r";
    if (request == "$BM") return "$BM,7.000," + std::to_string(++polls) + "\r";
    return typical_reply(request);
  });
  auto stream = rig.driver->start_stream();
  ASSERT_TRUE(stream) << stream.error().message;
  EXPECT_EQ(rig.driver->active_stream_mode(), StreamMode::polled);
  const auto samples = samples_of(take(**stream, 3));
  ASSERT_EQ(samples.size(), 3U);
  EXPECT_EQ(*samples[2].get(uls::channel::pulse_width_ps), 3U);
  rig.driver->stop_stream();
}

// U89: with CO off the unit still measures every PPM / PRF seconds (§2 Continuous Output: "When
// this function is off, the ULS completes measurements, but the display is not updated. You must
// select Single Measurement to display the last completed measurement"), and BM answers "the most
// recent measurement" (§2 Single Measurement). A BM sooner than one output period after the last
// answer gets the same measurement again: 2000 Hz / 100 PPM reported the first one twice, 2 ms apart.
// Here PF 2000 and PO 101 (50.5 ms); the unit numbers its measurements in the pulse width field and
// a BM before the first has completed waits for it.
TEST(UlsDriver, U89_PolledStreamReportsEachMeasurementOnce) {
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::microseconds(50500);
  Clock::time_point started;
  Rig rig([&](const std::string& request) -> std::string {
    if (request == "$CO") return "$CO,0\r";
    if (request == "$PO") return "$PO,101,1024\r";
    if (request == "$GO") {
      started = Clock::now();
      return "$OK\r";
    }
    if (request == "$BM") {
      auto completed = (Clock::now() - started) / period;
      if (completed == 0) {
        std::this_thread::sleep_until(started + period);  // the unit's first measurement takes one period
        completed = 1;
      }
      return "$BM,7.000," + std::to_string(completed) + "\r";
    }
    return typical_reply(request);
  });
  auto stream = rig.driver->start_stream();
  ASSERT_TRUE(stream) << stream.error().message;
  ASSERT_EQ(rig.driver->active_stream_mode(), StreamMode::polled);
  const auto samples = samples_of(take(**stream, 4));
  rig.driver->stop_stream();
  ASSERT_EQ(samples.size(), 4U);
  for (std::size_t i = 1; i < samples.size(); ++i)
    EXPECT_GT(*samples[i].get(uls::channel::pulse_width_ps), *samples[i - 1].get(uls::channel::pulse_width_ps))
        << "sample " << i << " repeats a measurement";
}

// A unit in look down with time between events on (§8 Look Down Mode: "$XXXX output at the
// start of presence detected", "$0 output at the start of no presence detected").
std::string look_down_reply(const std::string& request) {
  if (request == "$MM") return "$MM,3\r";
  if (request == "$TB") return "$TB,1\r";
  return typical_reply(request);
}

std::vector<Sample> look_down_samples(const std::vector<StreamItem>& items) {
  auto samples = samples_of(items);
  for (const auto& sample : samples) EXPECT_EQ(sample.kind, uls::kind::look_down);
  return samples;
}

// U87: §3 Look Down Mode, "the sensor continuously fires pulses and looks for a specific change
// in distance", and sends a line only at an edge: silence is normal, not a sign that the lines go
// to the other port (U62). One edge is one sample; the stream never starts polling, so the last
// edge is not repeated as new events.
TEST(UlsDriver, U87_LookDownSilenceIsNormalAndStartsNoPolling) {
  ScriptedDevice* device = nullptr;
  Rig rig([&](const std::string& request) -> std::string {
    if (request == "$GO") {
      device->send("$OK\r$0BB8\r");  // one presence edge, 3000 pulses after the last no-presence edge
      return "";
    }
    if (request == "$BM") return "$0BB8\r";  // a poll would read the last edge again
    return look_down_reply(request);
  });
  device = rig.device.get();
  auto stream = rig.driver->start_stream();  // automatic: CO is on
  ASSERT_TRUE(stream) << stream.error().message;
  auto items = take(**stream, 1);
  // Longer than U62's 1.5 s without a line (the wait is what is tested, not a synchronisation).
  const auto until = std::chrono::steady_clock::now() + 2s;
  while (std::chrono::steady_clock::now() < until)
    if (auto item = (*stream)->next(100ms)) items.push_back(std::move(*item));
  rig.device->send("$0\r");  // the object leaves: the next edge
  const auto more = take(**stream, 1);
  items.insert(items.end(), more.begin(), more.end());
  EXPECT_EQ(rig.driver->active_stream_mode(), StreamMode::continuous);
  rig.driver->stop_stream();
  const auto samples = look_down_samples(items);
  ASSERT_EQ(samples.size(), 2U);
  EXPECT_EQ(samples[0].get(uls::channel::presence), true);
  EXPECT_EQ(samples[0].get(uls::channel::pulses_between_events), 3000U);
  EXPECT_EQ(samples[1].get(uls::channel::presence), false);
  EXPECT_EQ(count_requests(*rig.device, "$BM"), 0U);
}

// U87: polled look down (CO off, or --mode polled) reads the state at each poll (§2 Single
// Measurement, "the most recent measurement"); a sample is reported when the answer changes, so
// an edge is one sample however many polls read it.
TEST(UlsDriver, U87_PolledLookDownReportsAnEdgeOnce) {
  std::atomic<int> polls{0};
  Rig rig([&](const std::string& request) -> std::string {
    if (request == "$BM") {
      const int poll = ++polls;
      return poll <= 3 ? "$0BB8\r" : poll <= 6 ? "$0\r" : "$0BB8\r";
    }
    return look_down_reply(request);
  });
  auto stream = rig.driver->start_stream(StreamMode::polled);
  ASSERT_TRUE(stream) << stream.error().message;
  const auto samples = look_down_samples(take(**stream, 3));
  rig.driver->stop_stream();
  ASSERT_EQ(samples.size(), 3U);
  EXPECT_EQ(samples[0].get(uls::channel::presence), true);
  EXPECT_EQ(samples[1].get(uls::channel::presence), false);
  EXPECT_EQ(samples[2].get(uls::channel::presence), true);  // a new edge, though its count equals the first one's
  EXPECT_EQ(samples[2].get(uls::channel::pulses_between_events), 3000U);
  EXPECT_GE(polls.load(), 7);
}

TEST(UlsDriver, AutomaticStreamPollsWhenNoContinuousLinesArriveOnThisPort) {
  // docs/conformance.md U62: CO on, but MO sends the lines to the other port.
  int polls = 0;
  Rig rig([&](const std::string& request) -> std::string {
    if (request == "$BM") return "$BM,8.000," + std::to_string(++polls) + "\r";
    return typical_reply(request);
  });
  auto stream = rig.driver->start_stream();
  ASSERT_TRUE(stream) << stream.error().message;
  EXPECT_EQ(rig.driver->active_stream_mode(), StreamMode::continuous);
  const auto items = take(**stream, 2);
  const auto samples = samples_of(items);
  ASSERT_EQ(samples.size(), 2U);
  EXPECT_EQ(rig.driver->active_stream_mode(), StreamMode::polled);
  // The switch to polling is not silent: a polling event comes
  // before the first polled sample and names the port.
  std::vector<StreamEventKind> kinds;
  for (const auto& item : items) {
    if (const auto* event = std::get_if<StreamEvent>(&item)) {
      kinds.push_back(event->kind);
      if (event->kind == StreamEventKind::polling) {
        EXPECT_NE(event->message.find("host"), std::string::npos);
      }
    } else {
      break;
    }
  }
  EXPECT_NE(std::find(kinds.begin(), kinds.end(), StreamEventKind::polling), kinds.end());
  EXPECT_DOUBLE_EQ(*samples[0].get(uls::channel::distance_m), 8.0);
  rig.driver->stop_stream();
}

TEST(UlsDriver, MidFrameDisconnectGivesAnEventAndTheStreamResumesOnReopen) {
  // docs/conformance.md U63
  std::mutex mutex;
  std::vector<std::unique_ptr<ScriptedDevice>> devices;
  auto handler = [&](ScriptedDevice** self) {
    return [&, self](const std::string& request) -> std::string {
      if (request == "$GO") {
        (*self)->send("$OK\r$BM,1.000,5\r$BM,2.0");  // the cable goes mid-frame
        return "";
      }
      return typical_reply(request);
    };
  };
  ScriptedDevice* first = nullptr;
  ScriptedDevice* second = nullptr;
  auto pair = make_loopback_pair("host", "device");
  DriverOptions options;
  options.timeout = 500ms;
  options.reconnect_interval = 20ms;
  ReopenFunction reopen = [&]() -> Result<TransportPtr> {
    std::lock_guard lock(mutex);
    auto again = make_loopback_pair("host", "device");
    devices.push_back(std::make_unique<ScriptedDevice>(std::move(again.b), handler(&second)));
    second = devices.back().get();
    return std::move(again.a);
  };
  Driver driver(std::move(pair.a), options, reopen);
  {
    std::lock_guard lock(mutex);
    devices.push_back(std::make_unique<ScriptedDevice>(std::move(pair.b), handler(&first)));
    first = devices.back().get();
  }
  auto stream = driver.start_stream(StreamMode::continuous);
  ASSERT_TRUE(stream) << stream.error().message;
  auto items = take(**stream, 1);
  ASSERT_EQ(samples_of(items).size(), 1U);
  first->unplug();
  // Disconnected, reconnected, then the second device's first sample.
  items = take(**stream, 1);
  std::vector<StreamEventKind> kinds;
  for (const auto& item : items)
    if (const auto* event = std::get_if<StreamEvent>(&item)) kinds.push_back(event->kind);
  ASSERT_GE(kinds.size(), 2U);
  EXPECT_NE(std::find(kinds.begin(), kinds.end(), StreamEventKind::disconnected), kinds.end());
  EXPECT_NE(std::find(kinds.begin(), kinds.end(), StreamEventKind::reconnected), kinds.end());
  const auto samples = samples_of(items);
  ASSERT_EQ(samples.size(), 1U);
  EXPECT_DOUBLE_EQ(*samples[0].get(uls::channel::distance_m), 1.0);  // not the half frame "$BM,2.0"
  driver.stop_stream(AfterStream::keep_measuring);
  EXPECT_FALSE(driver.streaming());
}

TEST(UlsDriver, WithoutReopenTheStreamFinishesOnDisconnect) {
  ScriptedDevice* device = nullptr;
  Rig rig([&](const std::string& request) -> std::string {
    if (request == "$GO") {
      device->send("$OK\r$BM,1.000,5\r");
      return "";
    }
    return typical_reply(request);
  });
  device = rig.device.get();
  auto stream = rig.driver->start_stream(StreamMode::continuous);
  ASSERT_TRUE(stream) << stream.error().message;
  ASSERT_EQ(samples_of(take(**stream, 1)).size(), 1U);
  rig.device->unplug();
  const auto until = std::chrono::steady_clock::now() + 10s;
  while (!(*stream)->finished() && std::chrono::steady_clock::now() < until) (void)(*stream)->next(50ms);
  EXPECT_TRUE((*stream)->finished());
  rig.driver->stop_stream(AfterStream::keep_measuring);
}

TEST(UlsDriver, BroadcastSendsAndWaitsForNothing) {
  Rig rig([](const std::string&) { return std::string(); });
  ASSERT_TRUE(rig.driver->broadcast("GO"));
  const std::array<std::string_view, 1> on{"1"};
  ASSERT_TRUE(rig.driver->broadcast("PT", on, 0xF3));
  ASSERT_TRUE(rig.device->wait_for_requests(2));
  EXPECT_EQ(rig.device->requests()[0], "#\xF0GO");
  EXPECT_EQ(rig.device->requests()[1], "#\xF3PT,1");
  EXPECT_FALSE(rig.driver->broadcast("MM"));  // a read cannot be broadcast
}

// U67 (rewritten): a get's reply can be byte-identical to a set request sent before it:
// "$SG,12.500" sets the short gate (§8 Set Short Gate) and is also the reply to "$SG". Once a
// request's reply has arrived, its echo cannot come any more, so the reply to the get is the
// reply, with and without an echoing adapter (found by the service's read-back).
TEST(UlsDriver, U67_AGetReplyEqualToAnEarlierSetIsNoEcho) {
  for (const bool echo : {false, true}) {
    std::string short_gate = "0.000";
    Rig rig([&](const std::string& request) -> std::string {
      std::string reply;
      if (request.rfind("$SG,", 0) == 0) {
        short_gate = request.substr(4);
        reply = "$OK\r";
      } else if (request == "$SG") {
        reply = "$SG," + short_gate + "\r";
      } else {
        reply = typical_reply(request);
      }
      return echo ? request + "\r" + reply : reply;
    });
    ASSERT_TRUE(rig.driver->set("SG", "12.500")) << "echo " << echo;
    auto values = rig.driver->get("SG");
    ASSERT_TRUE(values) << "echo " << echo << ": " << values.error().message;
    ASSERT_EQ(values->size(), 1U);
    EXPECT_EQ(values->front(), "12.500");
    EXPECT_EQ(rig.driver->counters().echoes, echo ? 3U : 0U);  // MU (the distance's units), the set, the get
    EXPECT_EQ(rig.driver->counters().retries, 0U);             // answered the first time, not by a retry
  }
}

// U67: a 2-wire RS-485 adapter without echo suppression hands the host its own
// request before the unit's reply. Gets (with and without an argument), sets,
// actions, BM, broadcasts and a polled stream all read the reply, not the echo.
TEST(UlsDriver, OwnRequestsEchoedByTheAdapterAreSkipped) {
  Rig rig([](const std::string& request) -> std::string {
    std::string reply;
    if (request == "$BR,1") reply = "$BR,1,115200\r";
    if (request == "$PF,1000") reply = "$OK\r";
    if (request == "$BM") reply = "$BM,12.500,2100\r";
    if (reply.empty()) reply = typical_reply(request);
    return request + "\r" + reply;  // the adapter's echo, then the unit
  });
  auto version = rig.driver->version();
  ASSERT_TRUE(version) << version.error().message;
  EXPECT_EQ(*version, "ULS 1.0,2026");
  auto prf = rig.driver->prf();
  ASSERT_TRUE(prf) << prf.error().message;
  EXPECT_EQ((*prf)[0], 2000U);
  auto baud = rig.driver->baud(BaudPort::output);
  ASSERT_TRUE(baud) << baud.error().message;
  EXPECT_EQ(*baud, 115200U);
  ASSERT_TRUE(rig.driver->set_prf(1000));
  auto reading = rig.driver->measure();
  ASSERT_TRUE(reading) << reading.error().message;
  EXPECT_DOUBLE_EQ(*reading->get(uls::channel::distance_m), 12.5);
  ASSERT_TRUE(rig.driver->broadcast("GO"));
  auto stream = rig.driver->start_stream(StreamMode::polled);
  ASSERT_TRUE(stream) << stream.error().message;
  const auto samples = samples_of(take(**stream, 3));
  rig.driver->stop_stream();
  ASSERT_EQ(samples.size(), 3U);
  EXPECT_DOUBLE_EQ(*samples[2].get(uls::channel::distance_m), 12.5);
  const DriverCounters counters = rig.driver->counters();
  EXPECT_EQ(counters.bad_frames, 0U);
  EXPECT_EQ(counters.retries, 0U);
  EXPECT_GE(counters.echoes, 10U);  // one per request sent
}

TEST(UlsDriver, ProbeReadsIdAndStatusOnly) {
  auto pair = make_loopback_pair("host", "device");
  ScriptedDevice device(std::move(pair.b), typical_reply);
  auto found = probe(*pair.a);
  ASSERT_TRUE(found) << found.error().message;
  EXPECT_EQ(found->version, "ULS 1.0,2026");
  EXPECT_EQ(found->status.value, 1);
  EXPECT_EQ(device.requests(), (std::vector<std::string>{"$ID", "$US"}));
  auto none = probe(*pair.a, std::uint8_t{'Q'}, 100ms);
  ASSERT_FALSE(none);
  EXPECT_EQ(none.error().code, Errc::timeout);
}

// docs/conformance.md U77: a unit already measuring answers GO with 31 "Instrument Is Already
// Measuring" (§10); starting is what the host asked for, so the stream runs on.
TEST(UlsDriver, U77_StartOnAUnitAlreadyMeasuringIsNoError) {
  ScriptedDevice* device = nullptr;
  Rig rig([&](const std::string& request) -> std::string {
    if (request == "$GO") {
      device->send("$ER,31\r$BM,12.500,2100\r");
      return "";
    }
    return typical_reply(request);
  });
  device = rig.device.get();
  auto stream = rig.driver->start_stream(StreamMode::continuous);
  ASSERT_TRUE(stream) << stream.error().message;
  const auto samples = samples_of(take(**stream, 1));
  ASSERT_EQ(samples.size(), 1U);
  EXPECT_DOUBLE_EQ(*samples[0].get(uls::channel::distance_m), 12.5);
  rig.driver->stop_stream();
}

// --- The stream is its own object, as the LS5 driver's -----------------------------------
// Every way to end it is safe whichever of the two objects goes first; the unit is left as
// U86 says (§8 Stop Measuring "ST": sent only when the stream's own GO started the unit).

// The driver goes first: the stream object stays readable, reads as finished, and sends
// nothing more when stopped or destroyed later (U86: exactly one ST, from the driver's end).
TEST(UlsDriver, U86_TheStreamOutlivesTheDriver) {
  MeasuringUnit unit;
  Rig rig([&](const std::string& request) { return unit.answer(request); });
  unit.device = rig.device.get();
  auto stream = rig.driver->start_stream(StreamMode::continuous);
  ASSERT_TRUE(stream) << stream.error().message;
  ASSERT_EQ(samples_of(take(**stream, 1)).size(), 1U);
  rig.driver.reset();
  EXPECT_FALSE(unit.measuring);
  EXPECT_EQ(count_requests(*rig.device, "$ST"), 1U);
  EXPECT_TRUE(drained_and_finished(**stream));
  EXPECT_FALSE((*stream)->next(0ms).has_value());
  EXPECT_EQ((*stream)->records(), 1U);
  EXPECT_EQ((*stream)->lost(), 0U);
  (*stream)->stop();
  (*stream)->stop(AfterStream::stop_measuring);  // ended already: nothing is sent
  stream->reset();
  EXPECT_EQ(count_requests(*rig.device, "$ST"), 1U);
  EXPECT_EQ(count_requests(*rig.device, "$GO"), 1U);
}

// The stream goes first: the driver reads the link for itself again, answers gets, and can
// start another stream, which again starts (GO) and stops (ST) the idle unit.
TEST(UlsDriver, U86_TheDriverOutlivesTheStream) {
  MeasuringUnit unit;
  Rig rig([&](const std::string& request) { return unit.answer(request); });
  unit.device = rig.device.get();
  {
    auto stream = rig.driver->start_stream(StreamMode::continuous);
    ASSERT_TRUE(stream) << stream.error().message;
    ASSERT_EQ(samples_of(take(**stream, 1)).size(), 1U);
    EXPECT_TRUE(rig.driver->streaming());
  }
  EXPECT_FALSE(rig.driver->streaming());
  EXPECT_FALSE(unit.measuring);
  EXPECT_EQ(count_requests(*rig.device, "$ST"), 1U);
  auto version = rig.driver->version();
  ASSERT_TRUE(version) << version.error().message;
  EXPECT_EQ(*version, "ULS 1.0,2026");
  auto again = rig.driver->start_stream(StreamMode::continuous);
  ASSERT_TRUE(again) << again.error().message;
  ASSERT_EQ(samples_of(take(**again, 1)).size(), 1U);
  rig.driver->stop_stream();  // from the driver's side: the stream object reads as finished
  EXPECT_TRUE(drained_and_finished(**again));
  EXPECT_EQ(count_requests(*rig.device, "$GO"), 2U);
  EXPECT_EQ(count_requests(*rig.device, "$ST"), 2U);
}

// One stream at a time: a second start_stream while one runs is refused, the first runs on.
TEST(UlsDriver, ASecondStreamIsRefusedWhileOneRuns) {
  MeasuringUnit unit;
  Rig rig([&](const std::string& request) { return unit.answer(request); });
  unit.device = rig.device.get();
  auto stream = rig.driver->start_stream(StreamMode::continuous);
  ASSERT_TRUE(stream) << stream.error().message;
  auto second = rig.driver->start_stream(StreamMode::continuous);
  ASSERT_FALSE(second);
  EXPECT_EQ(second.error().code, Errc::unsupported);
  ASSERT_EQ(samples_of(take(**stream, 1)).size(), 1U);
  EXPECT_EQ(count_requests(*rig.device, "$GO"), 1U);
}

// stop() twice, and from three threads at once (Ctrl-C, the consumer, the driver's side):
// the reader is joined once and ST goes out once (U86).
TEST(UlsDriver, U86_StopTwiceAndFromSeveralThreadsEndsTheStreamOnce) {
  MeasuringUnit unit;
  Rig rig([&](const std::string& request) { return unit.answer(request); });
  unit.device = rig.device.get();
  auto stream = rig.driver->start_stream(StreamMode::continuous);
  ASSERT_TRUE(stream) << stream.error().message;
  ASSERT_EQ(samples_of(take(**stream, 1)).size(), 1U);
  std::thread first([&] { (*stream)->stop(); });
  std::thread second([&] { (*stream)->stop(); });
  std::thread third([&] { rig.driver->stop_stream(); });
  first.join();
  second.join();
  third.join();
  (*stream)->stop();
  EXPECT_FALSE(unit.measuring);
  EXPECT_EQ(count_requests(*rig.device, "$ST"), 1U);
  EXPECT_TRUE(drained_and_finished(**stream));
  EXPECT_FALSE(rig.driver->streaming());
}

// A consumer waiting in next() on one thread is woken when another thread stops the stream:
// next() returns at once with nothing, not after its timeout, and the stream reads as finished.
// Meanwhile a third thread asks the unit's ID over and over: while the stream runs the reader
// hands the reply over, after it ended the caller reads the link itself; every get succeeds.
TEST(UlsDriver, NextAndGetsOnOtherThreadsWhileTheStreamStops) {
  MeasuringUnit unit;
  Rig rig([&](const std::string& request) { return unit.answer(request); });
  unit.device = rig.device.get();
  auto stream = rig.driver->start_stream(StreamMode::continuous);
  ASSERT_TRUE(stream) << stream.error().message;
  ASSERT_EQ(samples_of(take(**stream, 1)).size(), 1U);

  constexpr auto long_wait = std::chrono::minutes(10);  // far longer than the test may take
  std::atomic<bool> waiting{false};
  bool woken_early = false;
  bool finished_after = false;
  std::thread consumer([&] {
    waiting = true;
    const auto asked = std::chrono::steady_clock::now();
    const auto item = (*stream)->next(long_wait);
    woken_early = !item && std::chrono::steady_clock::now() - asked < long_wait;
    finished_after = (*stream)->finished();
  });
  std::atomic<int> answered{0};
  std::atomic<int> failed{0};
  std::thread asking([&] {
    for (int i = 0; i < 20; ++i) {
      auto version = rig.driver->version();
      if (version && *version == "ULS 1.0,2026") {
        ++answered;
      } else {
        ++failed;
      }
    }
  });
  while (!waiting || answered < 3) std::this_thread::yield();
  (*stream)->stop();
  consumer.join();
  asking.join();
  EXPECT_TRUE(woken_early);
  EXPECT_TRUE(finished_after);
  EXPECT_EQ(answered.load(), 20);
  EXPECT_EQ(failed.load(), 0);
  EXPECT_EQ(count_requests(*rig.device, "$ST"), 1U);
}

// A link whose read blocks until released or until the transport is destroyed, and that
// records a destruction during a read (which in a real transport would be a use after free).
struct BlockingReadState {
  std::mutex mutex;
  std::condition_variable changed;
  bool reading = false;
  bool destroyed = false;
  bool destroyed_during_read = false;
};
class BlockingReadTransport final : public Transport {
 public:
  explicit BlockingReadTransport(std::shared_ptr<BlockingReadState> state) : state_(std::move(state)) {}
  ~BlockingReadTransport() override {
    std::lock_guard lock(state_->mutex);
    state_->destroyed = true;
    state_->destroyed_during_read = state_->reading;
    state_->changed.notify_all();
  }
  Status write_all(Bytes) override { return ok_status(); }
  Result<std::size_t> read_some(std::span<std::uint8_t>, std::chrono::milliseconds timeout) override {
    const auto state = state_;  // `this` may be gone when the wait ends
    std::unique_lock lock(state->mutex);
    state->reading = true;
    state->changed.notify_all();
    state->changed.wait_for(lock, timeout, [&] { return state->destroyed; });
    state->reading = false;
    return make_error(Errc::timeout, "nothing");
  }
  void close() noexcept override {}
  [[nodiscard]] std::string name() const override { return "blocking"; }

 private:
  std::shared_ptr<BlockingReadState> state_;
};

// replace_transport waits for the request in flight: it takes the request lock, so a
// caller's read never runs on a transport that was destroyed under it.
TEST(UlsDriver, ReplaceTransportWaitsForTheRequestInFlight) {
  auto state = std::make_shared<BlockingReadState>();
  DriverOptions options;
  options.timeout = 200ms;
  options.read_retries = 0;
  Driver driver(std::make_unique<BlockingReadTransport>(state), options);
  std::thread asking([&] { (void)driver.version(); });
  {
    std::unique_lock lock(state->mutex);
    state->changed.wait(lock, [&] { return state->reading; });
  }
  auto other = make_loopback_pair("host", "device");
  EXPECT_TRUE(driver.replace_transport(std::move(other.a)).ok());
  asking.join();
  std::lock_guard lock(state->mutex);
  EXPECT_TRUE(state->destroyed);
  EXPECT_FALSE(state->destroyed_during_read);
}

// The stream's reader thread points at the driver: it cannot be copied
// or moved away from under the reader.
static_assert(!std::is_copy_constructible_v<Driver> && !std::is_move_constructible_v<Driver>);
static_assert(!std::is_copy_assignable_v<Driver> && !std::is_move_assignable_v<Driver>);

}  // namespace
}  // namespace rangekit::uls
