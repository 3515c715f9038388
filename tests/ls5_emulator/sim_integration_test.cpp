// `rangekit sim ls5` as a process: a host on the real pty, the control socket
// driving the virtual clock and the sync input, a loopback UDP receiver (conformance L36;
// L82: from the source port of parameters 6E/6F; L93: to the destination of 5C-5F and 6C/6D,
// --udp their first value).
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>

#include "ls5_driver/cli_process.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/core/udp.hpp"
#include "rangekit/ls5/ls5.hpp"
#include "rangekit/sim/control_socket.hpp"

namespace rangekit {
namespace {

using namespace std::chrono_literals;

using ls5_driver_test::Child;  // `rangekit sim ...` as a child, its stdout read line by line

struct Paths {
  std::filesystem::path dir;
  std::string port, control, scene;
  explicit Paths(const std::string& name) {
    dir = std::filesystem::temp_directory_path() / ("rangekit-ls5sim-" + name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    port = (dir / "ls5").string();
    control = (dir / "ctl").string();
    scene = (dir / "scene.toml").string();
  }
  ~Paths() { std::filesystem::remove_all(dir); }
};

std::string read_bytes(SerialPort& port, std::size_t expected, std::chrono::milliseconds timeout = 2000ms) {
  std::string text;
  std::array<std::uint8_t, 512> buffer{};
  while (text.size() < expected) {
    auto got = port.read_some(std::span(buffer.data(), expected - text.size()), timeout);
    if (!got || *got == 0) break;
    text.append(reinterpret_cast<const char*>(buffer.data()), *got);
  }
  return text;
}

struct Session {
  std::unique_ptr<SerialPort> host;
  std::optional<ControlClient> control;

  nlohmann::json ask(const nlohmann::json& request) {
    auto reply = control->request(request);
    EXPECT_TRUE(reply) << reply.error().message;
    return reply ? *reply : nlohmann::json{};
  }
  // Writes a request, lets 20 ms of virtual time pass, reads the expected reply length.
  std::string exchange(std::string_view request, std::size_t reply_length, std::chrono::milliseconds timeout = 2000ms) {
    EXPECT_TRUE(host->write_all(as_bytes(request)));
    ask({{"cmd", "status"}});  // the runtime has polled the pty by the time it answers
    ask({{"cmd", "advance"}, {"seconds", 0.02}});
    return read_bytes(*host, reply_length, timeout);
  }
};

Session connect(const Paths& paths) {
  Session session;
  auto host = SerialPort::open(paths.port, SerialSettings{115200, Parity::none, 1});
  EXPECT_TRUE(host) << host.error().message;
  if (host) session.host = std::move(*host);
  auto client = ControlClient::connect(paths.control);
  EXPECT_TRUE(client) << client.error().message;
  if (client) session.control.emplace(std::move(*client));
  return session;
}

TEST(Ls5Sim, BusOfTwoSensorsCommandsWeldingExampleAndUdp) {
  Paths paths("bus");
  { std::ofstream(paths.scene) << "[target]\nposition_mm = 50.0\nnoise_mm = 0.0\n"; }
  auto receiver = UdpSocket::bind(Endpoint{"127.0.0.1", 0});
  ASSERT_TRUE(receiver) << receiver.error().message;
  Child sim({"sim",
             "ls5",
             "--port",
             paths.port,
             "--address",
             "1",
             "--address",
             "2",
             "--model",
             "0/100",
             "--serial",
             "157",
             "--version",
             "LS5.12.0",
             "--udp",
             receiver->local_endpoint().to_string(),
             "--scene",
             paths.scene,
             "--control",
             paths.control,
             "--virtual-clock"});
  const std::string ready = sim.read_line();
  ASSERT_NE(ready.find("ready:"), std::string::npos) << ready;
  auto s = connect(paths);
  ASSERT_TRUE(s.host && s.control);

  // Identification and the §9.4 sessions.
  EXPECT_EQ(s.exchange("#01ID\r", 39), "%01LS5.12.0  b0,0000d100,000s/n0000157\r");
  EXPECT_EQ(s.exchange("#02ID\r", 39), "%02LS5.12.0  b0,0000d100,000s/n0000158\r");
  EXPECT_EQ(s.exchange("#01ON\r", 6), "!01ON\r");
  EXPECT_EQ(s.exchange("#02W0B01\r", 9), "!02W0B01\r");
  EXPECT_EQ(s.exchange("#01LR\r", 11), "!01LR25000\r");

  // §8.14 welding example on sensor 01, with the button on the sync input.
  for (const char* command : {"#01W2510\r", "#01W2627\r", "#01W1F09\r"}) {
    std::string echo = command;
    echo[0] = '!';
    EXPECT_EQ(s.exchange(command, 9), echo);
  }
  auto synced = s.ask({{"cmd", "sync"}, {"level", "pulse"}, {"address", 1}});
  EXPECT_EQ(synced["latched"], 25000) << synced.dump();
  EXPECT_EQ(s.exchange("#01R17\r", 9), "!01R174E\r");
  EXPECT_EQ(s.exchange("#01R1D\r", 9), "!01R1D75\r");
  EXPECT_EQ(s.exchange("#02R1D\r", 9), "!02R1DC3\r") << "sensor 02 keeps its default";

  auto outputs = s.ask({{"cmd", "outputs"}, {"address", 2}});
  EXPECT_EQ(outputs["unit"], "mA");
  EXPECT_TRUE(outputs.contains("oc1"));
  EXPECT_TRUE(s.ask({{"cmd", "outputs"}}).contains("error"));  // two sensors: name one

  // Ethernet: period 10 ms, 168 results = 1.68 s per packet from each sensor.
  s.ask({{"cmd", "advance"}, {"seconds", 2.0}});
  std::array<std::uint8_t, 1024> datagram{};
  std::set<std::uint16_t> serials;
  for (int i = 0; i < 2; ++i) {
    auto got = receiver->receive(datagram, 2000ms);
    ASSERT_TRUE(got) << got.error().message;
    ASSERT_EQ(got->size, ls5::udp_packet_size);
    auto packet = ls5::decode_udp_packet(Bytes(datagram.data(), got->size));
    ASSERT_TRUE(packet) << packet.error().message;
    EXPECT_EQ(packet->counter, 0);
    EXPECT_EQ(packet->range_mm, 100);
    EXPECT_TRUE(packet->records.back().in_range());
    serials.insert(packet->serial_number);
  }
  EXPECT_EQ(serials, (std::set<std::uint16_t>{157, 158}));

  EXPECT_EQ(s.ask({{"cmd", "shutdown"}})["ok"], true);
  EXPECT_EQ(sim.wait(), 0);
}

// A loopback UDP port free now: bound to port 0 and released, for a parameter to name.
std::uint16_t free_udp_port() {
  auto socket = UdpSocket::bind(Endpoint{"127.0.0.1", 0});
  EXPECT_TRUE(socket) << socket.error().message;
  return socket ? socket->local_endpoint().port : 0;
}

// A port held the way another program holds it: bound without SO_REUSEADDR, so nobody shares it.
struct HeldPort {
  int fd = -1;
  std::uint16_t port = 0;
  HeldPort() {
    fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    if (fd >= 0 && ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0) {
      port = ntohs(address.sin_port);
    }
  }
  ~HeldPort() { release(); }
  HeldPort(const HeldPort&) = delete;
  HeldPort& operator=(const HeldPort&) = delete;
  void release() {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
};

// Writes a port into the parameter pair at `high_parameter`, high byte first, as table 9.2 lists
// each port's high byte before its low one (source 6E/6F, destination 6C/6D).
void set_port(Session& s, unsigned high_parameter, std::uint16_t port) {
  char high[16];
  char low[16];
  std::snprintf(high, sizeof high, "#01W%02X%02X\r", high_parameter, port >> 8U);
  std::snprintf(low, sizeof low, "#01W%02X%02X\r", high_parameter + 1, port & 0xFFU);
  for (const char* command : {high, low}) {
    std::string echo = command;
    echo[0] = '!';
    EXPECT_EQ(s.exchange(command, 9), echo);
  }
}

void set_source_port(Session& s, std::uint16_t port) { set_port(s, 0x6E, port); }

// The next datagram's sender port, waiting for it up to 2 s after virtual time has moved a packet on.
std::optional<std::uint16_t> next_packet_port(Session& s, UdpSocket& receiver) {
  s.ask({{"cmd", "advance"}, {"seconds", 0.2}});  // t = 1 ms: a packet every 168 ms
  std::array<std::uint8_t, 1024> datagram{};
  auto got = receiver.receive(datagram, 2000ms);
  if (!got) return std::nullopt;
  EXPECT_EQ(got->size, ls5::udp_packet_size);
  return got->from.port;
}

TEST(Ls5Sim, UdpPacketsComeFromTheSourcePortTheParametersNameL82) {
  // Table 9.2 6E/6F "Source port number"; §10 "Source port number (sensor) 5000". Tests run side
  // by side, so this one names ports it found free instead of relying on 5000.
  Paths paths("srcport");
  auto receiver = UdpSocket::bind(Endpoint{"127.0.0.1", 0});
  ASSERT_TRUE(receiver) << receiver.error().message;
  Child sim({"sim", "ls5", "--port", paths.port, "--model", "0/100", "--version", "LS5.12.0", "--udp",
             receiver->local_endpoint().to_string(), "--control", paths.control, "--virtual-clock"});
  ASSERT_NE(sim.read_line().find("ready:"), std::string::npos);
  auto s = connect(paths);
  ASSERT_TRUE(s.host && s.control);
  EXPECT_EQ(s.exchange("#01W7000\r", 9), "!01W7000\r");  // no packets while the port is set
  EXPECT_EQ(s.exchange("#01W060A\r", 9), "!01W060A\r");  // t = 1 ms
  const std::uint16_t first = free_udp_port();
  set_source_port(s, first);
  EXPECT_EQ(s.exchange("#01W7001\r", 9), "!01W7001\r");
  EXPECT_EQ(next_packet_port(s, *receiver), first);
  EXPECT_EQ(s.ask({{"cmd", "outputs"}})["udp_source_port"], first);

  // A change is followed from the next packet on.
  EXPECT_EQ(s.exchange("#01W7000\r", 9), "!01W7000\r");
  const std::uint16_t second = free_udp_port();
  set_source_port(s, second);
  EXPECT_EQ(s.exchange("#01W7001\r", 9), "!01W7001\r");
  EXPECT_EQ(next_packet_port(s, *receiver), second);

  // A port another program holds: an error event on the control socket, no packet from any other
  // port, and the sensor goes on answering.
  HeldPort held;
  ASSERT_NE(held.port, 0);
  EXPECT_EQ(s.exchange("#01W7000\r", 9), "!01W7000\r");
  set_source_port(s, held.port);
  EXPECT_EQ(s.exchange("#01W7001\r", 9), "!01W7001\r");
  s.ask({{"cmd", "advance"}, {"seconds", 0.2}});
  auto outputs = s.ask({{"cmd", "outputs"}});
  ASSERT_TRUE(outputs["udp_error"].is_string()) << outputs.dump();
  EXPECT_NE(outputs["udp_error"].get<std::string>().find(std::to_string(held.port)), std::string::npos);
  EXPECT_GE(outputs["udp_unsent"], 1);
  EXPECT_EQ(s.exchange("#01R70\r", 9), "!01R7001\r");
  // Freed, the port is bound at the next packet, and the error clears.
  held.release();
  EXPECT_EQ(next_packet_port(s, *receiver), held.port);
  EXPECT_TRUE(s.ask({{"cmd", "outputs"}})["udp_error"].is_null());
  EXPECT_EQ(s.ask({{"cmd", "shutdown"}})["ok"], true);
  EXPECT_EQ(sim.wait(), 0);
}

void set_destination_port(Session& s, std::uint16_t port) { set_port(s, 0x6C, port); }

TEST(Ls5Sim, UdpPacketsGoWhereTheDestinationParametersSayL93) {
  // Table 9.2 "Destination IP address" 5C-5F and "Destination port number" 6C/6D; --udp gives
  // their first values. The default 255.255.255.255 reaches this host at 127.0.0.1.
  Paths paths("destination");
  auto first = UdpSocket::bind(Endpoint{"127.0.0.1", 0});
  auto second = UdpSocket::bind(Endpoint{"127.0.0.1", 0});
  ASSERT_TRUE(first && second);
  Child sim({"sim", "ls5", "--port", paths.port, "--model", "0/100", "--version", "LS5.12.0", "--udp",
             first->local_endpoint().to_string(), "--control", paths.control, "--virtual-clock"});
  ASSERT_NE(sim.read_line().find("ready:"), std::string::npos);
  auto s = connect(paths);
  ASSERT_TRUE(s.host && s.control);
  EXPECT_EQ(s.exchange("#01R5C\r", 9), "!01R5C7F\r");    // 127.0.0.1 from --udp
  EXPECT_EQ(s.exchange("#01W060A\r", 9), "!01W060A\r");  // t = 1 ms
  std::array<std::uint8_t, 1024> datagram{};
  s.ask({{"cmd", "advance"}, {"seconds", 0.2}});
  ASSERT_TRUE(first->receive(datagram, 2000ms));

  EXPECT_EQ(s.exchange("#01W7000\r", 9), "!01W7000\r");
  set_destination_port(s, second->local_endpoint().port);
  EXPECT_EQ(s.exchange("#01W7001\r", 9), "!01W7001\r");
  s.ask({{"cmd", "advance"}, {"seconds", 0.2}});
  auto got = second->receive(datagram, 2000ms);
  ASSERT_TRUE(got) << got.error().message;
  EXPECT_EQ(got->size, ls5::udp_packet_size);

  // DF: 255.255.255.255 (and 603, 10 ms); with the port set to the first receiver's again,
  // the broadcast arrives there through 127.0.0.1.
  EXPECT_EQ(s.exchange("#01DF\r", 6), "!01DF\r");
  EXPECT_EQ(s.ask({{"cmd", "outputs"}})["udp_destination"], "255.255.255.255:603");
  EXPECT_EQ(s.exchange("#01W7000\r", 9), "!01W7000\r");
  set_destination_port(s, first->local_endpoint().port);
  EXPECT_EQ(s.exchange("#01W060A\r", 9), "!01W060A\r");
  while (first->receive(datagram, 0ms)) {
  }  // what came before the DF
  EXPECT_EQ(s.exchange("#01W7001\r", 9), "!01W7001\r");
  s.ask({{"cmd", "advance"}, {"seconds", 0.2}});
  got = first->receive(datagram, 2000ms);
  ASSERT_TRUE(got) << got.error().message;
  EXPECT_EQ(s.ask({{"cmd", "outputs"}})["udp_destination"],
            "255.255.255.255:" + std::to_string(first->local_endpoint().port));
  EXPECT_EQ(s.ask({{"cmd", "shutdown"}})["ok"], true);
  EXPECT_EQ(sim.wait(), 0);
}

TEST(Ls5Sim, FlashSurvivesPowerCycleThroughTheControlSocket) {
  Paths paths("flash");
  const std::string state = (paths.dir / "state").string();
  Child sim({"sim", "ls5", "--port", paths.port, "--state", state, "--control", paths.control, "--virtual-clock"});
  ASSERT_NE(sim.read_line().find("ready:"), std::string::npos);
  auto s = connect(paths);
  ASSERT_TRUE(s.host && s.control);
  EXPECT_EQ(s.exchange("#01W0C04\r", 9), "!01W0C04\r");
  EXPECT_EQ(s.exchange("#01FL\r", 6), "!01FL\r");
  EXPECT_EQ(s.exchange("#01W0803\r", 9), "!01W0803\r");
  EXPECT_EQ(s.ask({{"cmd", "power_cycle"}})["ok"], true);
  EXPECT_EQ(s.exchange("#01R0C\r", 9), "!01R0C04\r");
  EXPECT_EQ(s.exchange("#01R08\r", 9), "!01R0801\r");
}

TEST(Ls5Sim, HostAtAnotherBaudSeesGarbage) {
  Paths paths("baud");
  Child sim({"sim", "ls5", "--port", paths.port, "--control", paths.control, "--virtual-clock"});
  ASSERT_NE(sim.read_line().find("ready:"), std::string::npos);
  auto s = connect(paths);
  ASSERT_TRUE(s.host && s.control);
  EXPECT_EQ(s.exchange("#01W0504\r", 9), "!01W0504\r");  // the sensor now talks at 57600
  // The request arrives garbled: no reply, or garbage (never a clean identification).
  EXPECT_NE(s.exchange("#01ID\r", 1, 300ms), "%");
}

TEST(Ls5Sim, EveryCommandAndTheSection95ExampleOverThePty) {
  Paths paths("commands");
  { std::ofstream(paths.scene) << "[target]\nposition_mm = 20.0\nnoise_mm = 0.0\n"; }
  Child sim({"sim", "ls5", "--port", paths.port, "--model", "LS5-0/50-232-U10-2-24-A", "--version", "LS5.9.0",
             "--scene", paths.scene, "--control", paths.control, "--virtual-clock"});
  ASSERT_NE(sim.read_line().find("ready:"), std::string::npos);
  auto s = connect(paths);
  ASSERT_TRUE(s.host && s.control);
  EXPECT_EQ(s.exchange("#01ID\r", 39), "%01LS5.9.0   b0,0000d50,0000s/n0000157\r");
  EXPECT_EQ(s.exchange("#01R70\r", 9, 300ms), "");  // RS-232 model: no Ethernet parameters
  // Table 9.3 (§9.5).
  for (const char* command :
       {"#01W1512\r", "#01W1620\r", "#01W174E\r", "#01W1840\r", "#01W199C\r", "#01W1A10\r", "#01W1B27\r", "#01W1C30\r",
        "#01W1D75\r", "#01W0301\r", "#01W1100\r", "#01W1200\r", "#01W1350\r", "#01W14C3\r"}) {
    std::string echo = command;
    echo[0] = '!';
    EXPECT_EQ(s.exchange(command, 9), echo);
  }
  s.ask({{"cmd", "advance"}, {"seconds", 0.05}});
  auto outputs = s.ask({{"cmd", "outputs"}});  // code 20000 (20 mm of 50): OC1 on at its first swing
  EXPECT_EQ(outputs["result"], 20000);
  EXPECT_EQ(outputs["oc1"], true);
  EXPECT_EQ(outputs["oc2"], false);
  EXPECT_EQ(outputs["unit"], "V");
  EXPECT_NEAR(outputs["analog"].get<double>(), 4.0, 1e-9);  // 0-10 V: 20000 / 50000 × 10 V
  EXPECT_EQ(s.ask({{"cmd", "move_target"}, {"position_mm", 5.0}})["ok"], true);
  s.ask({{"cmd", "advance"}, {"seconds", 0.05}});
  outputs = s.ask({{"cmd", "outputs"}});
  EXPECT_EQ(outputs["oc1"], false);
  EXPECT_EQ(outputs["oc2"], true);
  EXPECT_NEAR(outputs["analog"].get<double>(), 1.0, 1e-9);
  // The other commands of table 9.1.
  EXPECT_EQ(s.exchange("#01FX\r", 6), "!01FX\r");
  EXPECT_EQ(s.exchange("#01FR\r", 11), "!01FR05000\r");
  EXPECT_EQ(s.exchange("#01LR\r", 11), "!01LR05000\r");
  EXPECT_EQ(s.exchange("#01OF\r", 6), "!01OF\r");
  EXPECT_EQ(s.ask({{"cmd", "outputs"}})["oc2"], false);
  EXPECT_EQ(s.exchange("#01ON\r", 6), "!01ON\r");
  EXPECT_TRUE(s.host->write_all(as_bytes("#01ST\r")));
  s.ask({{"cmd", "status"}});
  s.ask({{"cmd", "advance"}, {"seconds", 0.035}});
  EXPECT_EQ(read_bytes(*s.host, 21), "!05000\r!05000\r!05000\r");
  EXPECT_EQ(s.exchange("#01SB\r", 6), "!01SB\r");
  EXPECT_EQ(s.exchange("#01DF\r", 6), "!01DF\r");
  EXPECT_EQ(s.exchange("#01R15\r", 9), "!01R1512\r");
  EXPECT_EQ(s.exchange("#01R17\r", 9), "!01R1700\r");
}

TEST(Ls5Sim, StandbyAt19200AfterPowerCycleWithAFastStoredBaud) {
  Paths paths("standby");
  Child sim(
      {"sim", "ls5", "--port", paths.port, "--version", "LS5.6.0", "--control", paths.control, "--virtual-clock"});
  ASSERT_NE(sim.read_line().find("ready:"), std::string::npos);
  auto s = connect(paths);
  ASSERT_TRUE(s.host && s.control);
  EXPECT_EQ(s.exchange("#01W0506\r", 9), "!01W0506\r");  // 230400 from now on
  s.host.reset();
  auto fast = SerialPort::open(paths.port, SerialSettings{230400, Parity::none, 1});
  ASSERT_TRUE(fast) << fast.error().message;
  s.host = std::move(*fast);
  EXPECT_EQ(s.exchange("#01FL\r", 6), "!01FL\r");
  EXPECT_EQ(s.ask({{"cmd", "power_cycle"}})["phase"], "initializing");
  s.ask({{"cmd", "advance"}, {"seconds", 4.5}});
  EXPECT_EQ(s.ask({{"cmd", "outputs"}})["phase"], "standby");
  s.host.reset();
  auto slow = SerialPort::open(paths.port, SerialSettings{19200, Parity::none, 1});
  ASSERT_TRUE(slow) << slow.error().message;
  s.host = std::move(*slow);
  EXPECT_EQ(s.exchange("#01R05\r", 9), "!01R0506\r");  // standby talks 19200 8N1 (§8.2)
  s.ask({{"cmd", "advance"}, {"seconds", 5.0}});
  EXPECT_EQ(s.ask({{"cmd", "outputs"}})["phase"], "operating");
  s.host.reset();
  auto again = SerialPort::open(paths.port, SerialSettings{230400, Parity::none, 1});
  ASSERT_TRUE(again) << again.error().message;
  s.host = std::move(*again);
  EXPECT_EQ(s.exchange("#01R05\r", 9), "!01R0506\r");
}

// L28 on the real-time runtime: the echo of a baud write leaves at the old speed
// and must reach a host still at that speed intact (it once arrived garbled, the
// bytes judged against the new speed), and the sensor answers at the new one after.
TEST(Ls5Sim, BaudWriteEchoReachesTheHostAtTheOldSpeed) {
  Paths paths("baudecho");
  Child sim({"sim", "ls5", "--port", paths.port});
  ASSERT_NE(sim.read_line().find("ready:"), std::string::npos);
  auto host = SerialPort::open(paths.port, SerialSettings{115200, Parity::none, 1});
  ASSERT_TRUE(host) << host.error().message;
  ASSERT_TRUE((*host)->write_all(as_bytes(std::string_view("#01W0508\r"))));  // 921600 (table 9.2)
  EXPECT_EQ(read_bytes(**host, 9), "!01W0508\r");
  host->reset();
  auto fast = SerialPort::open(paths.port, SerialSettings{921600, Parity::none, 1});
  ASSERT_TRUE(fast) << fast.error().message;
  ASSERT_TRUE((*fast)->write_all(as_bytes(std::string_view("#01R05\r"))));
  EXPECT_EQ(read_bytes(**fast, 9), "!01R0508\r");
}

TEST(Ls5Sim, SameAddressTwiceCollidesOnTheBus) {
  Paths paths("collide");
  Child sim({"sim", "ls5", "--port", paths.port, "--address", "1", "--address", "1", "--control", paths.control,
             "--virtual-clock"});
  ASSERT_NE(sim.read_line().find("ready:"), std::string::npos);
  auto s = connect(paths);
  ASSERT_TRUE(s.host && s.control);
  const std::string reply = s.exchange("#01R06\r", 9, 500ms);
  EXPECT_EQ(reply.size(), 9U);  // both answer at once: 9 corrupted bytes, not two clean replies
  EXPECT_NE(reply, "!01R0664\r");
}

TEST(Ls5Sim, SigtermShutsDownCleanly) {
  Paths paths("sigterm");
  Child sim({"sim", "ls5", "--port", paths.port, "--control", paths.control});
  ASSERT_NE(sim.read_line().find("ready:"), std::string::npos);
  EXPECT_TRUE(std::filesystem::is_symlink(paths.port));
  sim.terminate();
  EXPECT_EQ(sim.wait(), 0);
  EXPECT_FALSE(std::filesystem::exists(paths.port));
  EXPECT_FALSE(std::filesystem::exists(paths.control));
}

TEST(Ls5Sim, BadArgumentsAreUsageErrors) {
  Child bad_model({"sim", "ls5", "--model", "forty"});
  EXPECT_EQ(bad_model.wait(), 2);
  Child bad_address({"sim", "ls5", "--address", "0"});
  EXPECT_EQ(bad_address.wait(), 2);
  Child bad_destination({"sim", "ls5", "--udp", "127.0.0.1:0"});  // table 9.2: destination port 0001-FFFF
  EXPECT_EQ(bad_destination.wait(), 2);
}

}  // namespace
}  // namespace rangekit
