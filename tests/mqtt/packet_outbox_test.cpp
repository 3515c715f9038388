// The fast path's send buffer (docs/mqtt.md): packets leave whole and in order through a
// socket that takes only part of them at a time, it says when part of a packet is on the
// wire (the bridge then lets libmosquitto write nothing), a dead peer is a failure and
// not a SIGPIPE, and the packets reach a real mosquitto byte for byte at every size of
// Remaining Length (1 to 4 bytes), written on a libmosquitto session's own socket as the
// bridge writes them.
#include <gtest/gtest.h>
#include <mosquitto.h>
#include <mqtt_protocol.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <string>
#include <vector>

#include "mqtt/packet_outbox.hpp"
#include "mqtt_fixture.hpp"

namespace {

using rangekit::mqtt::PacketOutbox;
using namespace std::chrono_literals;

struct Published {
  std::string topic;
  std::string payload;
};

// The test's own reading of a stream of QoS 0 PUBLISH packets (MQTT 5.0 §3.3), independent
// of the encoder: fixed header 0x30, Remaining Length (§1.5.5), topic, Property Length 0, payload.
std::vector<Published> parse(const std::string& stream) {
  std::vector<Published> out;
  std::size_t at = 0;
  while (at < stream.size()) {
    EXPECT_EQ(static_cast<unsigned char>(stream[at]), 0x30U);
    ++at;
    std::size_t length = 0;
    std::size_t multiplier = 1;
    unsigned char byte = 0;
    do {
      byte = static_cast<unsigned char>(stream.at(at++));
      length += (byte & 0x7FU) * multiplier;
      multiplier *= 128;
    } while ((byte & 0x80U) != 0);
    const std::size_t end = at + length;
    const std::size_t topic_length =
        static_cast<unsigned char>(stream.at(at)) * 256U + static_cast<unsigned char>(stream.at(at + 1));
    Published packet;
    packet.topic = stream.substr(at + 2, topic_length);
    at += 2 + topic_length;
    EXPECT_EQ(stream.at(at), '\0');  // no properties
    ++at;
    packet.payload = stream.substr(at, end - at);
    at = end;
    out.push_back(std::move(packet));
  }
  return out;
}

std::string payload_of(std::size_t index, std::size_t size) {
  std::string payload(size, static_cast<char>('a' + index % 26));
  payload.replace(0, std::min(size, std::to_string(index).size()), std::to_string(index), 0, size);
  return payload;
}

struct SocketPair {
  std::array<int, 2> fds{-1, -1};
  SocketPair() {
    EXPECT_EQ(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0, fds.data()), 0);
    const int small = 4096;  // the writer's buffer: a packet of 1000 bytes goes in parts
    ::setsockopt(fds[0], SOL_SOCKET, SO_SNDBUF, &small, sizeof small);
  }
  ~SocketPair() {
    for (const int fd : fds) {
      if (fd >= 0) ::close(fd);
    }
  }
  SocketPair(const SocketPair&) = delete;
  SocketPair& operator=(const SocketPair&) = delete;
  std::string read_all() const {
    std::string got;
    std::array<char, 65536> buffer{};
    for (;;) {
      const ssize_t n = ::read(fds[1], buffer.data(), buffer.size());
      if (n <= 0) return got;
      got.append(buffer.data(), static_cast<std::size_t>(n));
    }
  }
};

TEST(PacketOutbox, PacketsLeaveWholeAndInOrderThroughASocketThatTakesPartsOfThem) {
  SocketPair pair;
  PacketOutbox outbox;
  constexpr std::size_t count = 300;
  for (std::size_t i = 0; i < count; ++i) ASSERT_TRUE(outbox.add("site/belt-1/reading", payload_of(i, 1000)));
  EXPECT_EQ(outbox.packets(), count);

  std::string received;
  std::size_t completed = 0;
  bool seen_mid_packet = false;
  for (int round = 0; round < 100000 && !outbox.empty(); ++round) {
    const auto result = outbox.write_to(pair.fds[0]);
    completed += outbox.take_completed();
    if (result == PacketOutbox::Write::blocked) {
      // A packet is 1 + 2 + (2 + 19 + 1 + 1000) = 1025 bytes: part of one is on the wire
      // exactly when what went so far is not a whole number of packets.
      received += pair.read_all();  // all that was sent so far
      const std::size_t sent = received.size();
      EXPECT_EQ(outbox.mid_packet(), sent % 1025 != 0);
      seen_mid_packet = seen_mid_packet || outbox.mid_packet();
      EXPECT_EQ(completed, sent / 1025);
    } else {
      ASSERT_EQ(result, PacketOutbox::Write::done);
    }
  }
  received += pair.read_all();
  completed += outbox.take_completed();
  EXPECT_TRUE(outbox.empty());
  EXPECT_FALSE(outbox.mid_packet());
  EXPECT_EQ(completed, count);
  EXPECT_TRUE(seen_mid_packet) << "the socket never took part of a packet: the test did not test that";
  const auto packets = parse(received);
  ASSERT_EQ(packets.size(), count);
  for (std::size_t i = 0; i < count; ++i) {
    EXPECT_EQ(packets[i].topic, "site/belt-1/reading");
    EXPECT_EQ(packets[i].payload, payload_of(i, 1000)) << "packet " << i;
  }
}

TEST(PacketOutbox, AGonePeerIsAFailureNotASignalAndDropCountsWhatWasLeft) {
  SocketPair pair;
  ::close(pair.fds[1]);
  pair.fds[1] = -1;
  PacketOutbox outbox;
  ASSERT_TRUE(outbox.add("a/b", "one"));
  ASSERT_TRUE(outbox.add("a/b", "two"));
  EXPECT_EQ(outbox.write_to(pair.fds[0]), PacketOutbox::Write::failed);  // EPIPE, and the test still runs
  EXPECT_EQ(outbox.take_completed(), 0U);
  EXPECT_EQ(outbox.drop(), 2U);
  EXPECT_TRUE(outbox.empty());
  EXPECT_EQ(outbox.drop(), 0U);
}

TEST(PacketOutbox, APacketOverTheBrokersMaximumIsRefusedAndNothingIsAdded) {
  PacketOutbox outbox;
  // "a/b" with "hi" is 10 bytes (publish_packet_test): 10 fits a limit of 10, not of 9.
  EXPECT_FALSE(outbox.add("a/b", "hi", 9));
  EXPECT_TRUE(outbox.empty());
  EXPECT_TRUE(outbox.add("a/b", "hi", 10));
  EXPECT_EQ(outbox.packets(), 1U);
}

// A libmosquitto session of the test's own, driven without a thread as the bridge drives its.
class Session {
 public:
  explicit Session(std::uint16_t port) {
    client_ = mosquitto_new(("rangekit-outbox-" + std::to_string(::getpid())).c_str(), true, this);
    mosquitto_int_option(client_, MOSQ_OPT_PROTOCOL_VERSION, MQTT_PROTOCOL_V5);
    mosquitto_connect_v5_callback_set(client_, [](mosquitto*, void* self, int rc, int, const mosquitto_property*) {
      static_cast<Session*>(self)->connected_ = rc == 0;
    });
    connect_rc_ = mosquitto_connect(client_, "127.0.0.1", port, 30);
  }
  ~Session() {
    mosquitto_disconnect(client_);
    mosquitto_destroy(client_);
  }
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  bool wait_connected() {
    for (int i = 0; i < 600 && connect_rc_ == MOSQ_ERR_SUCCESS && !connected_; ++i) mosquitto_loop(client_, 100, 1);
    return connected_;
  }
  void step() { mosquitto_loop(client_, 10, 1); }
  void publish(const std::string& topic, const std::string& payload) {
    mosquitto_publish(client_, nullptr, topic.c_str(), static_cast<int>(payload.size()), payload.data(), 0, false);
  }
  [[nodiscard]] int socket() const { return mosquitto_socket(client_); }
  [[nodiscard]] bool wants_write() const { return mosquitto_want_write(client_); }

 private:
  mosquitto* client_ = nullptr;
  int connect_rc_ = MOSQ_ERR_UNKNOWN;
  bool connected_ = false;
};

TEST(PacketOutbox, PacketsOnALibmosquittoSessionsSocketReachARealBrokerByteForByte) {
  mqtt_test::Broker broker;
  ASSERT_TRUE(broker.broker);
  mqtt_test::Subscriber subscriber(broker.port(), {"fast/#"});
  ASSERT_TRUE(subscriber.wait_subscribed());
  mosquitto_lib_init();
  Session session(broker.port());
  ASSERT_TRUE(session.wait_connected());
  // The subscription is in place once a probe comes back (CONNACK alone does not say so).
  bool heard_probe = false;
  for (int i = 0; i < 300 && !heard_probe; ++i) {
    session.publish("fast/probe", "probe");
    session.step();
    heard_probe = subscriber.wait_for([](const std::vector<mqtt_test::Heard>& heard) { return !heard.empty(); },
                                      std::chrono::seconds(1));
  }
  ASSERT_TRUE(heard_probe);
  subscriber.clear();

  // Remaining Length of 1, 2, 3 and 4 bytes (§1.5.5), and an empty payload.
  const std::vector<std::size_t> sizes{0, 1, 100, 200, 20'000, 2'200'000};
  PacketOutbox outbox;
  for (std::size_t i = 0; i < sizes.size(); ++i) ASSERT_TRUE(outbox.add("fast/reading", payload_of(i, sizes[i])));
  while (!outbox.empty()) {
    ASSERT_FALSE(session.wants_write());  // nothing of libmosquitto's may be cut by ours
    ASSERT_NE(outbox.write_to(session.socket()), PacketOutbox::Write::failed);
    pollfd fd{session.socket(), POLLOUT, 0};
    ::poll(&fd, 1, 1000);
  }
  EXPECT_EQ(outbox.take_completed(), sizes.size());
  ASSERT_TRUE(
      subscriber.wait_for([&](const std::vector<mqtt_test::Heard>& heard) { return heard.size() >= sizes.size(); }));
  const auto heard = subscriber.heard();
  ASSERT_EQ(heard.size(), sizes.size());
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    EXPECT_EQ(heard[i].topic, "fast/reading");
    EXPECT_EQ(heard[i].payload.size(), sizes[i]);
    EXPECT_TRUE(heard[i].payload == payload_of(i, sizes[i])) << "payload " << i << " differs";
  }
  // The session is still in order: the broker did not drop it for a malformed packet.
  session.publish("fast/after", "after");
  for (int i = 0; i < 100; ++i) session.step();
  EXPECT_TRUE(subscriber.wait_for(
      [](const std::vector<mqtt_test::Heard>& all) { return !all.empty() && all.back().topic == "fast/after"; }));
}

}  // namespace
