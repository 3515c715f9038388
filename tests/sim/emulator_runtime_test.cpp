// The emulator runtime over real pseudo-terminals, with a trivial echo device
// on the virtual clock: pacing, line faults, bus collisions, control socket.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "rangekit/sim/emulator_runtime.hpp"
#include "rangekit/sim/serial_pacer.hpp"

namespace rangekit {
namespace {

using namespace std::chrono_literals;

// Answers every byte it receives with the same byte, at its own baud.
class EchoDevice final : public DeviceModel {
 public:
  explicit EchoDevice(std::uint32_t baud, std::string label = "echo")
      : settings_{baud, Parity::none, 1}, pacer_(baud, 1000), label_(std::move(label)) {}
  [[nodiscard]] std::size_t port_count() const noexcept override { return 1; }
  [[nodiscard]] SerialSettings port_settings(std::size_t) const override { return settings_; }
  void receive(std::size_t, std::uint8_t byte, Nanos now) override {
    pacer_.send(Bytes(&byte, 1), now);
    ++received;
  }
  void advance(Nanos) override {}
  [[nodiscard]] Nanos next_deadline() const override { return pacer_.next_completion(); }
  void take_line_output(std::size_t, Nanos now, std::vector<LineByte>& out) override {
    while (pacer_.next_completion() <= now) {
      const Nanos done = pacer_.next_completion();
      std::vector<std::uint8_t> bytes;
      pacer_.take_sent(done, bytes);
      for (const auto value : bytes) out.push_back(LineByte{done, value});
    }
  }
  nlohmann::json control(const nlohmann::json&, Nanos) override { return {{"echo", true}}; }
  [[nodiscard]] std::string label() const override { return label_; }
  int received = 0;

 private:
  SerialSettings settings_;
  SerialPacer pacer_;
  std::string label_;
};

std::string read_available(Transport& port, std::size_t expected) {
  std::string text;
  std::array<std::uint8_t, 256> buffer{};
  while (text.size() < expected) {
    auto got = port.read_some(buffer, 500ms);
    if (!got) break;
    text.append(reinterpret_cast<const char*>(buffer.data()), *got);
  }
  return text;
}

struct Rig {
  std::unique_ptr<EmulatorRuntime> runtime;
  std::unique_ptr<SerialPort> host;
};

Rig make_rig(std::vector<DeviceModel*> devices, std::uint32_t host_baud, std::optional<std::string> control = {},
             std::optional<std::string> wire_log = {}) {
  LineConfig line{"bus", std::nullopt, {}};
  for (auto* device : devices) line.attachments.push_back(LineAttachment{device, 0});
  RuntimeOptions options;
  options.virtual_clock = true;
  options.control_path = std::move(control);
  options.wire_log_path = std::move(wire_log);
  auto runtime = EmulatorRuntime::create({line}, options);
  EXPECT_TRUE(runtime) << runtime.error().message;
  auto host = SerialPort::open((*runtime)->line_path(0), SerialSettings{host_baud, Parity::none, 1});
  EXPECT_TRUE(host) << host.error().message;
  return Rig{std::move(*runtime), std::move(*host)};
}

// Feeds the host's bytes to the runtime: written bytes are in the pty as soon as write returns.
void deliver(Rig& rig, std::string_view text) {
  ASSERT_TRUE(rig.host->write_all(as_bytes(text)));
  ASSERT_TRUE(rig.runtime->step(0ns));
}

TEST(EmulatorRuntime, BytesComeBackOnlyOnceTheirTimeHasCome) {
  EchoDevice echo(9600);
  auto rig = make_rig({&echo}, 9600);
  deliver(rig, "AB");
  EXPECT_EQ(echo.received, 2);
  // 9600 baud 8N1: 1.0417 ms per byte. Before the first byte is done, nothing.
  ASSERT_TRUE(rig.runtime->advance_to(1ms));
  std::array<std::uint8_t, 8> buffer{};
  EXPECT_FALSE(rig.host->read_some(buffer, 20ms));
  ASSERT_TRUE(rig.runtime->advance_to(3ms));
  EXPECT_EQ(read_available(*rig.host, 2), "AB");
}

TEST(EmulatorRuntime, HostAtTheWrongBaudSeesGarbage) {
  EchoDevice echo(115200);
  auto rig = make_rig({&echo}, 9600);
  deliver(rig, "HELLO");
  ASSERT_TRUE(rig.runtime->advance_to(10ms));
  const std::string back = read_available(*rig.host, 5);
  EXPECT_EQ(back.size(), 5U);
  EXPECT_NE(back, "HELLO");
}

TEST(EmulatorRuntime, TwoDevicesTalkingAtOnceCollide) {
  EchoDevice first(115200, "first");
  EchoDevice second(115200, "second");
  auto rig = make_rig({&first, &second}, 115200);
  deliver(rig, "Q");
  ASSERT_TRUE(rig.runtime->advance_to(1ms));
  const std::string back = read_available(*rig.host, 1);
  ASSERT_EQ(back.size(), 1U);  // one corrupted byte, not two clean ones
  EXPECT_NE(back, "Q");
}

TEST(EmulatorRuntime, DroppedBytesNeverArrive) {
  EchoDevice echo(115200);
  auto rig = make_rig({&echo}, 115200);
  rig.runtime->set_noise(0, LineNoise{0.0, 1.0});
  deliver(rig, "ABC");
  ASSERT_TRUE(rig.runtime->advance_to(1ms));
  std::array<std::uint8_t, 8> buffer{};
  EXPECT_FALSE(rig.host->read_some(buffer, 20ms));
}

// Line noise may duplicate bytes: a duplicated byte arrives twice; the wire log (the noise
// bench's truth) holds what the device sent, before any line noise.
TEST(EmulatorRuntime, DuplicatedBytesArriveTwiceAndTheWireLogHoldsWhatWasSent) {
  const auto log = std::filesystem::temp_directory_path() / ("rangekit-wire-" + std::to_string(::getpid()));
  {
    EchoDevice echo(115200);
    auto rig = make_rig({&echo}, 115200, std::nullopt, log.string());
    rig.runtime->set_noise(0, LineNoise{0.0, 0.0, 1.0});
    deliver(rig, "ABC");
    ASSERT_TRUE(rig.runtime->advance_to(1ms));
    EXPECT_EQ(read_available(*rig.host, 6), "AABBCC");
    rig.runtime->set_noise(0, LineNoise{1.0, 0.0, 0.0});  // every bit flipped
    deliver(rig, "D");
    ASSERT_TRUE(rig.runtime->advance_to(2ms));
    EXPECT_EQ(read_available(*rig.host, 1), std::string(1, static_cast<char>('D' ^ 0xFF)));
  }
  std::ifstream file(log, std::ios::binary);
  const std::string logged((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  EXPECT_EQ(logged, "ABCD");
  std::filesystem::remove(log);
}

TEST(EmulatorRuntime, ControlSocketStatusAdvanceAndErrors) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("rangekit-ctl-" + std::to_string(::getpid()))).string();
  std::filesystem::remove(path);
  EchoDevice echo(115200);
  auto rig = make_rig({&echo}, 115200, path);
  auto client = ControlClient::connect(path);
  ASSERT_TRUE(client) << client.error().message;
  // The runtime answers while stepping; a helper thread plays the event loop.
  std::atomic<bool> stop{false};
  std::thread loop([&] { (void)rig.runtime->run(stop); });
  auto status = client->request({{"cmd", "status"}});
  ASSERT_TRUE(status);
  EXPECT_EQ((*status)["virtual_clock"], true);
  EXPECT_EQ((*status)["lines"][0]["devices"][0], "echo");
  auto advanced = client->request({{"cmd", "advance"}, {"seconds", 1.5}});
  ASSERT_TRUE(advanced);
  EXPECT_DOUBLE_EQ((*advanced)["time_s"].get<double>(), 1.5);
  auto unknown = client->request({{"cmd", "warp"}});
  ASSERT_TRUE(unknown);
  EXPECT_NE((*unknown)["error"].get<std::string>().find("unknown command 'warp'"), std::string::npos);
  auto wrong_type = client->request({{"cmd", "advance"}, {"seconds", "soon"}});
  ASSERT_TRUE(wrong_type);
  EXPECT_TRUE(wrong_type->contains("error"));
  stop = true;
  loop.join();
  rig.runtime.reset();
  EXPECT_FALSE(std::filesystem::exists(path));
}

// docs/conformance.md U47
TEST(EmulatorRuntime, ControlExtensionActsAtTheRuntimesPresent) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("rangekit-ctl-now-" + std::to_string(::getpid()))).string();
  std::filesystem::remove(path);
  EchoDevice echo(115200);
  auto rig = make_rig({&echo}, 115200, path);
  std::vector<Nanos> seen;
  rig.runtime->set_control_extension([&seen](const nlohmann::json& request, Nanos now) -> nlohmann::json {
    if (request.value("cmd", "") != "when") return nullptr;  // not ours: the runtime answers
    seen.push_back(now);
    return {{"ok", true}, {"time_ns", now.count()}};
  });
  auto client = ControlClient::connect(path);
  ASSERT_TRUE(client) << client.error().message;
  std::atomic<bool> stop{false};
  std::thread loop([&] { (void)rig.runtime->run(stop); });
  auto first = client->request({{"cmd", "when"}});
  ASSERT_TRUE(first);
  EXPECT_EQ((*first)["time_ns"], 0);
  ASSERT_TRUE(client->request({{"cmd", "advance"}, {"seconds", 2.25}}));
  auto second = client->request({{"cmd", "when"}});
  ASSERT_TRUE(second);
  EXPECT_EQ((*second)["time_ns"], 2'250'000'000LL);  // the clock's time, not the devices' last run
  auto other = client->request({{"cmd", "warp"}});
  ASSERT_TRUE(other);
  EXPECT_NE((*other)["error"].get<std::string>().find("unknown command 'warp'"), std::string::npos);
  stop = true;
  loop.join();
  EXPECT_EQ(seen.size(), 2U);
}

TEST(EmulatorRuntime, SymlinkAndControlPathsAreCheckedUpFront) {
  const auto link = std::filesystem::temp_directory_path() / ("rangekit-link-" + std::to_string(::getpid()));
  std::filesystem::remove(link);
  { std::ofstream(link.string()) << "occupied"; }
  EchoDevice echo(115200);
  auto runtime =
      EmulatorRuntime::create({LineConfig{"port", link.string(), {LineAttachment{&echo, 0}}}}, RuntimeOptions{});
  ASSERT_FALSE(runtime);
  EXPECT_NE(runtime.error().message.find("already exists"), std::string::npos);
  std::filesystem::remove(link);
}

// L78: LS5 manual §8.4: "When the stream is running, data is sent to the sensor output with
// a period T=n×t", and table 9.2: "Measurement period (discrete – 0.1 ms, minimum value –
// 0.1 ms)". A deadline 0.3 ms away must be waited for 0.3 ms, not a whole millisecond (the
// loop's old poll() rounded up, so records at 1 kHz left in millisecond batches).
TEST(EmulatorRuntimeLoopWait, L78_WaitsToTheNanosecondForSubMillisecondDeadlines) {
  EXPECT_EQ(loop_wait(300us, 50ms, Nanos(0)), 300us);
  EXPECT_EQ(loop_wait(Nanos(86'805), 50ms, Nanos(0)), Nanos(86'805));  // one 10-bit byte at 115200 baud
  EXPECT_EQ(loop_wait(1ms + 100us, 50ms, Nanos(0)), 1ms + 100us);
}

TEST(EmulatorRuntimeLoopWait, L78_NeverWaitsPastMaxWaitOrBelowZero) {
  EXPECT_EQ(loop_wait(2s, 50ms, Nanos(0)), 50ms);
  EXPECT_EQ(loop_wait(-5us, 50ms, Nanos(0)), Nanos(0));  // an overdue deadline: no wait at all
}

TEST(EmulatorRuntimeLoopWait, L78_ResolutionRoundsUpForTheBenchComparison) {
  // RuntimeOptions::wait_resolution = 1 ms reproduces the old loop in bench/emulator_pacing_bench.cpp.
  EXPECT_EQ(loop_wait(300us, 50ms, 1ms), 1ms);
  EXPECT_EQ(loop_wait(1ms, 50ms, 1ms), 1ms);
  EXPECT_EQ(loop_wait(1ms + 1ns, 50ms, 1ms), 2ms);
  EXPECT_EQ(loop_wait(Nanos(0), 50ms, 1ms), Nanos(0));
}

}  // namespace
}  // namespace rangekit
