// The measurement stream against scripted bytes: records become Samples (§8.9),
// bad records become bad_frame events, a link that closes mid-frame gives
// disconnected, and the stream comes back (reconnected, ST again) on a new link.
#include <gtest/gtest.h>

#include <thread>
#include <type_traits>

#include "rangekit/ls5/family.hpp"
#include "rangekit/ls5/settings.hpp"
#include "scripted_device.hpp"

using namespace rangekit;
using namespace rangekit::ls5;
using namespace ls5_driver_test;

namespace {

// Next item that is a Sample (events before it are collected), within 5 s.
struct Collected {
  std::vector<Sample> samples;
  std::vector<StreamEvent> events;
};

// Pops until `want` returns true for what was collected so far, or 10 s pass.
template <class Want>
Collected collect(SampleSource& source, Want want) {
  Collected collected;
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (!want(collected) && std::chrono::steady_clock::now() < deadline) {
    auto item = source.next(200ms);
    if (!item) continue;
    if (auto* sample = std::get_if<Sample>(&*item)) {
      collected.samples.push_back(*sample);
    } else {
      collected.events.push_back(std::get<StreamEvent>(*item));
    }
  }
  return collected;
}

bool has_event(const Collected& c, StreamEventKind kind) {
  for (const auto& event : c.events) {
    if (event.kind == kind) return true;
  }
  return false;
}

}  // namespace

TEST(Ls5Stream, RecordsBecomeSamplesWithThinningWrittenFirst) {
  auto pair = make_loopback_pair("ls5 line", "device");
  ScriptedDevice device(std::move(pair.b));
  Driver driver(std::move(pair.a), fast_options());
  device.send(id_reply_01);
  device.send("!01W0804\r");  // n = 4 (§8.4)
  Driver::StreamOptions options;
  options.thinning = 4;
  auto stream = driver.start_stream(options);
  ASSERT_TRUE(stream) << stream.error().message;
  EXPECT_EQ(device.receive_until("#01ST\r"), "#01ID\r#01W0804\r#01ST\r");

  device.send("!25000\r!65534\r!65535\r!00000\r");  // §8.9
  auto got = collect(**stream, [](const Collected& c) { return c.samples.size() >= 4; });
  ASSERT_EQ(got.samples.size(), 4U);
  EXPECT_EQ(got.samples[0].device, "ls5");
  EXPECT_EQ(got.samples[0].address, 1);
  EXPECT_EQ(got.samples[0].source, "ls5 line");
  EXPECT_EQ(got.samples[0].get(ls5::channel::code), 25000);
  EXPECT_EQ(got.samples[0].get(ls5::channel::signal), ls5::SignalState::ok);
  ASSERT_TRUE(got.samples[0].get(ls5::channel::distance_mm).has_value());
  EXPECT_DOUBLE_EQ(*got.samples[0].get(ls5::channel::distance_mm), 40.001 * 25000 / 50000);  // formula 8.1
  EXPECT_EQ(got.samples[1].get(ls5::channel::signal), ls5::SignalState::none_yet);
  EXPECT_FALSE(got.samples[1].get(ls5::channel::distance_mm).has_value());
  EXPECT_EQ(got.samples[2].get(ls5::channel::signal), ls5::SignalState::lost);
  EXPECT_FALSE(got.samples[2].get(ls5::channel::distance_mm).has_value());
  EXPECT_DOUBLE_EQ(got.samples[3].get(ls5::channel::distance_mm).value_or(-1), 0.0);
  // L69: the one event is `connected`, queued ahead of the records once ST went out.
  ASSERT_EQ(got.events.size(), 1U);
  EXPECT_EQ(got.events[0].kind, StreamEventKind::connected);
  EXPECT_EQ(got.events[0].message, "ls5 line: streaming (ST)");

  device.send("!01SB\r");
  (*stream)->stop();
  EXPECT_TRUE((*stream)->finished());
  EXPECT_EQ(device.receive_until("#01SB\r"), "#01SB\r");
}

TEST(Ls5Stream, MalformedRecordsAreReportedAndTheStreamGoesOn) {
  auto pair = make_loopback_pair();
  ScriptedDevice device(std::move(pair.b));
  Driver driver(std::move(pair.a), fast_options());
  device.send(id_reply_01);
  auto stream = driver.start_stream({});
  ASSERT_TRUE(stream) << stream.error().message;
  // A code above 50000 and not special (L7), bad digits, garbage, a record cut by the next (F3).
  device.send("!50001\r!2A000\r\x01\x02!123!10000\r");
  auto got = collect(**stream, [](const Collected& c) { return !c.samples.empty() && c.events.size() >= 5; });
  ASSERT_EQ(got.samples.size(), 1U);
  EXPECT_EQ(got.samples[0].get(ls5::channel::code), 10000);
  ASSERT_GE(got.events.size(), 5U);
  EXPECT_EQ(got.events[0].kind, StreamEventKind::connected);  // L69: the first item
  for (std::size_t i = 1; i < got.events.size(); ++i)
    EXPECT_EQ(got.events[i].kind, StreamEventKind::bad_frame) << got.events[i].message;
}

TEST(Ls5Stream, SlowConsumerNeverBlocksTheReaderAndLossesAreCounted) {
  auto pair = make_loopback_pair();
  ScriptedDevice device(std::move(pair.b));
  Driver driver(std::move(pair.a), fast_options());
  device.send(id_reply_01);
  Driver::StreamOptions options;
  options.queue_capacity = 4;
  auto stream = driver.start_stream(options);
  ASSERT_TRUE(stream) << stream.error().message;
  std::string records;
  for (int i = 0; i < 10; ++i) records += "!0000" + std::to_string(i) + "\r";
  device.send(records);
  // Nobody consumes: the reader keeps reading, the queue drops the oldest.
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while ((*stream)->records() < 10 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::yield();
  }
  EXPECT_EQ((*stream)->records(), 10U);
  EXPECT_EQ((*stream)->lost(), 7U);  // the `connected` event (L69) and the 6 oldest records
  auto first = (*stream)->next(1000ms);
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(std::get<Sample>(*first).get(ls5::channel::code), 6) << "the newest four are kept";
}

// docs/conformance.md L43
TEST(Ls5Stream, MidFrameDisconnectThenReconnectOnANewLink) {
  auto pair = make_loopback_pair("first link", "device");
  ScriptedDevice device(std::move(pair.b));
  std::mutex mutex;
  std::unique_ptr<ScriptedDevice> second_device;
  int reopen_calls = 0;
  // The first reopen fails (port not back yet), the second gives a new link.
  ReopenFunction reopen = [&]() -> Result<TransportPtr> {
    std::lock_guard lock(mutex);
    if (++reopen_calls == 1) return make_error(Errc::io, "no such port yet");
    auto next = make_loopback_pair("second link", "device 2");
    second_device = std::make_unique<ScriptedDevice>(std::move(next.b));
    return std::move(next.a);
  };
  DriverOptions driver_options = fast_options();
  driver_options.timeout = 2000ms;
  Driver driver(std::move(pair.a), driver_options, reopen);
  device.send(id_reply_01);
  Driver::StreamOptions options;
  options.reconnect_interval = 20ms;
  auto stream = driver.start_stream(options);
  ASSERT_TRUE(stream) << stream.error().message;
  device.send("!25000\r!250");  // the cable is pulled inside the second record
  device.close();

  auto lost = collect(**stream, [](const Collected& c) { return has_event(c, StreamEventKind::disconnected); });
  ASSERT_EQ(lost.samples.size(), 1U);
  ASSERT_TRUE(has_event(lost, StreamEventKind::bad_frame)) << "the half record is reported";
  ASSERT_TRUE(has_event(lost, StreamEventKind::disconnected));

  // The new link: the driver asks ID, then ST.
  ScriptedDevice* again = nullptr;
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (again == nullptr && std::chrono::steady_clock::now() < deadline) {
    {
      std::lock_guard lock(mutex);
      again = second_device.get();
    }
    if (again == nullptr) (void)(*stream)->next(20ms);
  }
  ASSERT_NE(again, nullptr);
  EXPECT_EQ(again->receive_until("#01ID\r"), "#01ID\r");
  again->send(id_reply_01);
  EXPECT_EQ(again->receive_until("#01ST\r"), "#01ST\r");
  again->send("!30000\r");
  auto back = collect(**stream, [](const Collected& c) { return !c.samples.empty(); });
  EXPECT_TRUE(has_event(back, StreamEventKind::reconnected));
  ASSERT_EQ(back.samples.size(), 1U);
  EXPECT_EQ(back.samples[0].get(ls5::channel::code), 30000);
  EXPECT_GE(reopen_calls, 2);
  (*stream)->stop();
}

TEST(Ls5Stream, SilenceIsTakenForAPowerCycleAndTheStreamIsRestarted) {
  auto pair = make_loopback_pair();
  ScriptedDevice device(std::move(pair.b));
  DriverOptions driver_options = fast_options();
  driver_options.timeout = 2000ms;
  Driver driver(std::move(pair.a), driver_options);
  device.send(id_reply_01);
  Driver::StreamOptions options;
  options.silence_timeout = 200ms;
  options.reconnect_interval = 20ms;
  auto stream = driver.start_stream(options);
  ASSERT_TRUE(stream) << stream.error().message;
  EXPECT_EQ(device.receive_until("#01ST\r"), "#01ID\r#01ST\r");
  device.send("!10000\r");
  auto quiet = collect(**stream, [](const Collected& c) { return has_event(c, StreamEventKind::disconnected); });
  ASSERT_TRUE(has_event(quiet, StreamEventKind::disconnected));
  // The sensor is back after its power cycle: it answers ID and streams again.
  EXPECT_EQ(device.receive_until("#01ID\r"), "#01ID\r");
  device.send(id_reply_01);
  EXPECT_EQ(device.receive_until("#01ST\r"), "#01ST\r");
  device.send("!20000\r");
  auto back = collect(**stream, [](const Collected& c) { return !c.samples.empty(); });
  EXPECT_TRUE(has_event(back, StreamEventKind::reconnected));
  ASSERT_FALSE(back.samples.empty());
  EXPECT_EQ(back.samples.back().get(ls5::channel::code), 20000);
}

TEST(Ls5Stream, WithoutAReopenFunctionAClosedLinkEndsTheStream) {
  auto pair = make_loopback_pair();
  ScriptedDevice device(std::move(pair.b));
  Driver driver(std::move(pair.a), fast_options());
  device.send(id_reply_01);
  Driver::StreamOptions options;
  options.reconnect_interval = 10ms;
  auto stream = driver.start_stream(options);
  ASSERT_TRUE(stream) << stream.error().message;
  device.close();
  auto got = collect(**stream, [&stream](const Collected&) { return (*stream)->finished(); });
  EXPECT_TRUE((*stream)->finished());
  EXPECT_TRUE(has_event(got, StreamEventKind::disconnected));
}

// U86 "the device is idle after ... a destroyed driver": the driver going
// first stops the stream it started. §8.13 "To stop the stream, use the #[AA]SB<cr> command."
// The stream left behind is finished and safe to read and stop (it shares what it reads with).
TEST(Ls5Stream, U86_DestroyingTheDriverFirstStopsItsStreamAndLeavesTheSensorIdle) {
  auto pair = make_loopback_pair("ls5 line", "device");
  ScriptedDevice device(std::move(pair.b));
  auto driver = std::make_unique<Driver>(std::move(pair.a), fast_options());
  device.send(id_reply_01);
  auto stream = driver->start_stream({});
  ASSERT_TRUE(stream) << stream.error().message;
  EXPECT_EQ(device.receive_until("#01ST\r"), "#01ID\r#01ST\r");
  device.send("!25000\r");
  auto got = collect(**stream, [](const Collected& c) { return !c.samples.empty(); });
  ASSERT_EQ(got.samples.size(), 1U);

  device.send("!01SB\r");  // the echo of SB (table 9.1 "Stop the stream")
  driver.reset();
  EXPECT_EQ(device.receive_until("#01SB\r"), "#01SB\r");
  EXPECT_TRUE((*stream)->finished());
  EXPECT_FALSE((*stream)->next(10ms).has_value());
  (*stream)->stop();  // nothing more is sent, nothing is touched
  stream->reset();
  EXPECT_EQ(device.receive_all(), "");
}

// While a stream holds the line, the driver refuses every call that would
// use it (its reply would be lost among the records, and the reader owns the line), naming
// the stream; after stop() the driver answers again.
TEST(Ls5Stream, CallsWhileTheStreamHoldsTheLineAreRefusedNamingTheStream) {
  auto pair = make_loopback_pair("ls5 line", "device");
  ScriptedDevice device(std::move(pair.b));
  Driver driver(std::move(pair.a), fast_options());
  device.send(id_reply_01);
  auto stream = driver.start_stream({});
  ASSERT_TRUE(stream) << stream.error().message;
  EXPECT_EQ(device.receive_until("#01ST\r"), "#01ID\r#01ST\r");
  EXPECT_TRUE(driver.streaming());

  auto last = driver.read_last();
  ASSERT_FALSE(last);
  EXPECT_EQ(last.error().code, Errc::unsupported);
  EXPECT_NE(last.error().message.find("measurement stream started on ls5 line"), std::string::npos)
      << last.error().message;
  EXPECT_FALSE(driver.write_parameter(0x08, 4));
  EXPECT_FALSE(driver.context());
  EXPECT_FALSE(driver.start_stream({}));
  EXPECT_EQ(device.receive_all(), "");  // nothing reached the line

  device.send("!01SB\r");
  (*stream)->stop();
  EXPECT_EQ(device.receive_until("#01SB\r"), "#01SB\r");
  EXPECT_FALSE(driver.streaming());
  device.send("!01LR25000\r");  // table 9.1 LR
  auto again = driver.read_last();
  ASSERT_TRUE(again) << again.error().message;
  EXPECT_EQ(again->code.value, 25000);
}

// What stop() means, alike in both families: the driver's stop_stream() ends the
// stream it started (reader joined, SB sent: §8.13 "To stop the stream, use the #[AA]SB<cr>
// command"), as the ULS driver's does; the stream object is then finished.
TEST(Ls5Stream, StopStreamOnTheDriverEndsTheStreamItStarted) {
  auto pair = make_loopback_pair("ls5 line", "device");
  ScriptedDevice device(std::move(pair.b));
  Driver driver(std::move(pair.a), fast_options());
  device.send(id_reply_01);
  auto stream = driver.start_stream({});
  ASSERT_TRUE(stream) << stream.error().message;
  EXPECT_EQ(device.receive_until("#01ST\r"), "#01ID\r#01ST\r");
  // The echo is sent once SB arrived: the reader is joined by then, so the driver reads it.
  Status stopped = ok_status();
  std::thread stopping([&] { stopped = driver.stop_stream(); });
  EXPECT_EQ(device.receive_until("#01SB\r"), "#01SB\r");
  device.send("!01SB\r");
  stopping.join();
  EXPECT_TRUE(stopped) << stopped.error().message;
  EXPECT_FALSE(driver.streaming());
  EXPECT_TRUE((*stream)->finished());
  stream->reset();
  EXPECT_EQ(device.receive_all(), "");  // the stream sends no second SB
}

// Misuse cannot compile: a stream points at the driver that started it, so
// neither a driver nor a stream can be copied or moved away from under the other.
static_assert(!std::is_copy_constructible_v<Driver> && !std::is_move_constructible_v<Driver>);
static_assert(!std::is_copy_assignable_v<Driver> && !std::is_move_assignable_v<Driver>);
static_assert(!std::is_copy_constructible_v<MeasurementStream> && !std::is_move_constructible_v<MeasurementStream>);
static_assert(!std::is_constructible_v<MeasurementStream, Driver&, const Driver::StreamOptions&>);
