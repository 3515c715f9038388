// Transports: in-memory loopback pair, pseudo-terminal with a serial client,
// UDP on the loopback address. No timing assumptions beyond generous timeouts.
#include <gtest/gtest.h>

#include <unistd.h>
#include <array>
#include <filesystem>
#include <string>
#include <thread>

#include "rangekit/core/loopback.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/core/udp.hpp"
#include "rangekit/sim/pty.hpp"

namespace rangekit {
namespace {

using namespace std::chrono_literals;

std::string read_exactly(Transport& transport, std::size_t count) {
  std::string text;
  std::array<std::uint8_t, 256> buffer{};
  while (text.size() < count) {
    auto got = transport.read_some(std::span(buffer).first(std::min(buffer.size(), count - text.size())), 2000ms);
    if (!got) return text + "<" + got.error().message + ">";
    text.append(reinterpret_cast<const char*>(buffer.data()), *got);
  }
  return text;
}

TEST(Loopback, BytesCrossBothWays) {
  auto pair = make_loopback_pair();
  ASSERT_TRUE(pair.a->write_all(as_bytes("$GO\r")));
  EXPECT_EQ(read_exactly(*pair.b, 4), "$GO\r");
  ASSERT_TRUE(pair.b->write_all(as_bytes("$OK\r")));
  EXPECT_EQ(read_exactly(*pair.a, 4), "$OK\r");
}

TEST(Loopback, TimeoutIsAnErrorValue) {
  auto pair = make_loopback_pair();
  std::array<std::uint8_t, 4> buffer{};
  auto got = pair.a->read_some(buffer, 1ms);
  ASSERT_FALSE(got);
  EXPECT_EQ(got.error().code, Errc::timeout);
}

TEST(Loopback, CloseDeliversPendingBytesThenClosed) {
  auto pair = make_loopback_pair();
  ASSERT_TRUE(pair.a->write_all(as_bytes("!01ON\r")));
  pair.a->close();
  EXPECT_EQ(read_exactly(*pair.b, 6), "!01ON\r");
  std::array<std::uint8_t, 4> buffer{};
  auto got = pair.b->read_some(buffer, 100ms);
  ASSERT_FALSE(got);
  EXPECT_EQ(got.error().code, Errc::closed);
  auto write = pair.b->write_all(as_bytes("x"));
  ASSERT_FALSE(write);
  EXPECT_EQ(write.error().code, Errc::closed);
}

TEST(Loopback, ReaderWakesWhenDataArrivesFromAnotherThread) {
  auto pair = make_loopback_pair();
  std::thread writer([&] { (void)pair.a->write_all(as_bytes("#01ID\r")); });
  EXPECT_EQ(read_exactly(*pair.b, 6), "#01ID\r");
  writer.join();
}

TEST(PseudoTerminal, SerialClientAndMasterExchangeBytesIntact) {
  auto pty = PseudoTerminal::open();
  ASSERT_TRUE(pty) << pty.error().message;
  auto port = SerialPort::open((*pty)->slave_path(), SerialSettings{115200, Parity::none, 1});
  ASSERT_TRUE(port) << port.error().message;
  std::string all_bytes;
  for (int i = 0; i < 256; ++i) all_bytes.push_back(static_cast<char>(i));
  ASSERT_TRUE((*port)->write_all(as_bytes(all_bytes)));
  EXPECT_EQ(read_exactly(**pty, 256), all_bytes);
  ASSERT_TRUE((*pty)->write_all(as_bytes(all_bytes)));
  EXPECT_EQ(read_exactly(**port, 256), all_bytes);
}

TEST(PseudoTerminal, MasterSeesTheClientsLineSettings) {
  auto pty = PseudoTerminal::open();
  ASSERT_TRUE(pty);
  auto port = SerialPort::open((*pty)->slave_path(), SerialSettings{19200, Parity::even, 2});
  ASSERT_TRUE(port) << port.error().message;
  auto seen = (*pty)->peer_settings();
  ASSERT_TRUE(seen) << seen.error().message;
  EXPECT_EQ(seen->baud, 19200U);
  EXPECT_EQ(seen->stop_bits, 2);
  ASSERT_TRUE((*port)->reconfigure(SerialSettings{921600, Parity::none, 1}));
  EXPECT_EQ((*pty)->peer_settings()->baud, 921600U);
  EXPECT_EQ((*pty)->peer_settings()->stop_bits, 1);
}

// Linux's pty driver drops PARENB from the shared termios (seen on this
// machine's kernel), so parity cannot be read back through a pty; the
// emulators treat parity as unknown there (docs/conformance.md H2).
TEST(PseudoTerminal, ParityIsReadBackWhenTheKernelKeepsIt) {
  auto pty = PseudoTerminal::open();
  ASSERT_TRUE(pty);
  auto port = SerialPort::open((*pty)->slave_path(), SerialSettings{19200, Parity::odd, 1});
  ASSERT_TRUE(port);
  auto own = read_serial_settings((*port)->native_handle());
  ASSERT_TRUE(own);
  if (own->parity == Parity::none) GTEST_SKIP() << "this kernel's pty does not keep the parity bit";
  EXPECT_EQ((*pty)->peer_settings()->parity, Parity::odd);
}

TEST(PseudoTerminal, ClientGoingAwayIsReportedAsClosed) {
  auto pty = PseudoTerminal::open();
  ASSERT_TRUE(pty);
  {
    auto port = SerialPort::open((*pty)->slave_path(), SerialSettings{});
    ASSERT_TRUE(port);
    ASSERT_TRUE((*port)->write_all(as_bytes("x")));
    EXPECT_EQ(read_exactly(**pty, 1), "x");
  }
  std::array<std::uint8_t, 8> buffer{};
  auto got = (*pty)->read_some(buffer, 500ms);
  ASSERT_FALSE(got);
  EXPECT_EQ(got.error().code, Errc::closed);
}

TEST(PseudoTerminal, SymlinkIsCreatedRefusedIfPresentAndRemoved) {
  const auto link = std::filesystem::temp_directory_path() / ("rangekit-pty-" + std::to_string(::getpid()));
  std::filesystem::remove(link);
  {
    auto pty = PseudoTerminal::open(link.string());
    ASSERT_TRUE(pty) << pty.error().message;
    EXPECT_TRUE(std::filesystem::is_symlink(link));
    EXPECT_EQ(std::filesystem::read_symlink(link).string(), (*pty)->slave_path());
    auto second = PseudoTerminal::open(link.string());
    ASSERT_FALSE(second);
    EXPECT_NE(second.error().message.find("already exists"), std::string::npos);
  }
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(link)));
}

TEST(SerialPort, MissingDeviceGivesAClearError) {
  auto port = SerialPort::open("/dev/rangekit-no-such-port", SerialSettings{});
  ASSERT_FALSE(port);
  EXPECT_NE(port.error().message.find("/dev/rangekit-no-such-port"), std::string::npos);
}

TEST(SerialPort, NonTerminalIsRefused) {
  auto port = SerialPort::open("/dev/null", SerialSettings{});
  ASSERT_FALSE(port);
  EXPECT_EQ(port.error().code, Errc::unsupported);
}

TEST(SerialPort, UnsupportedBaudIsRefusedWithTheRate) {
  auto pty = PseudoTerminal::open();
  ASSERT_TRUE(pty);
  auto port = SerialPort::open((*pty)->slave_path(), SerialSettings{250000, Parity::none, 1});
  ASSERT_FALSE(port);
  EXPECT_EQ(port.error().code, Errc::unsupported);
  EXPECT_NE(port.error().message.find("250000"), std::string::npos);
}

// docs/conformance.md H1: ULS §9 lists 14400 baud, which termios cannot set.
TEST(SerialPort, UlsBaud14400IsRefusedClearly) {
  auto pty = PseudoTerminal::open();
  ASSERT_TRUE(pty);
  auto port = SerialPort::open((*pty)->slave_path(), SerialSettings{14400, Parity::none, 1});
  ASSERT_FALSE(port);
  EXPECT_EQ(port.error().code, Errc::unsupported);
  EXPECT_NE(port.error().message.find("14400 baud is not a speed this system's serial driver can set"),
            std::string::npos)
      << port.error().message;
}

TEST(SerialSettings, BitsPerByte) {
  EXPECT_EQ((SerialSettings{115200, Parity::none, 1}.bits_per_byte()), 10);
  EXPECT_EQ((SerialSettings{115200, Parity::even, 1}.bits_per_byte()), 11);
  EXPECT_EQ((SerialSettings{115200, Parity::odd, 2}.bits_per_byte()), 12);
  EXPECT_EQ(describe(SerialSettings{19200, Parity::none, 1}), "19200 8N1");
}

TEST(Udp, DatagramOnLoopback) {
  auto receiver = UdpSocket::bind(Endpoint{"127.0.0.1", 0});
  ASSERT_TRUE(receiver) << receiver.error().message;
  auto sender = UdpSocket::bind(Endpoint{"127.0.0.1", 0});
  ASSERT_TRUE(sender);
  std::array<std::uint8_t, 512> packet{};
  for (std::size_t i = 0; i < packet.size(); ++i) packet[i] = static_cast<std::uint8_t>(i);
  ASSERT_TRUE(sender->send_to(packet, receiver->local_endpoint()));
  std::array<std::uint8_t, 512> buffer{};
  auto got = receiver->receive(buffer, 2000ms);
  ASSERT_TRUE(got) << got.error().message;
  EXPECT_EQ(got->size, 512U);
  EXPECT_EQ(buffer, packet);
  EXPECT_EQ(got->from.port, sender->local_endpoint().port);
}

TEST(Udp, OversizedDatagramIsReportedNotCut) {
  auto receiver = UdpSocket::bind(Endpoint{"127.0.0.1", 0});
  auto sender = UdpSocket::bind(Endpoint{"127.0.0.1", 0});
  ASSERT_TRUE(receiver && sender);
  std::array<std::uint8_t, 600> packet{};
  ASSERT_TRUE(sender->send_to(packet, receiver->local_endpoint()));
  std::array<std::uint8_t, 512> buffer{};
  auto got = receiver->receive(buffer, 2000ms);
  ASSERT_FALSE(got);
  EXPECT_EQ(got.error().code, Errc::overlong);
  EXPECT_NE(got.error().message.find("600"), std::string::npos);
}

TEST(Udp, EndpointParsing) {
  auto endpoint = parse_endpoint("127.0.0.1:603");
  ASSERT_TRUE(endpoint);
  EXPECT_EQ(endpoint->port, 603);
  EXPECT_FALSE(parse_endpoint("127.0.0.1"));
  EXPECT_FALSE(parse_endpoint("127.0.0.1:70000"));
  EXPECT_FALSE(parse_endpoint("not-an-ip:5000"));
}

}  // namespace
}  // namespace rangekit
