// The Modbus face on a live hub of emulators (hub/site_fixture.hpp), asked by libmodbus's own
// client as a PLC's gateway driver would: readings, exceptions, commands, a lost sensor, and
// clients that send what is no Modbus.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <modbus.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <bit>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <thread>

#include "hub/site_fixture.hpp"
#include "modbus/register_map.hpp"
#include "rangekit/core/family.hpp"
#include "rangekit/hub/hub.hpp"
#include "rangekit/modbus/face.hpp"

namespace {

using namespace rangekit;
using namespace std::chrono_literals;

struct LiveFace {
  hub_test::Site site;
  std::unique_ptr<hub::Hub> hub = hub::Hub::start(site.config);
  std::unique_ptr<modbus::Face> face;
  std::uint16_t port = 0;
  explicit LiveFace(bool writable) {
    modbus::FaceOptions options;
    options.listen = "127.0.0.1:0";
    options.writable = writable;
    options.units = hub::modbus_units(site.config);  // belt 1, silo 2, bay-A..D 3-6
    auto started = modbus::Face::start(*hub, options);
    EXPECT_TRUE(started.ok()) << (started.ok() ? "" : started.error().message);
    if (started) face = std::move(*started);
    if (face) port = face->local_endpoint().port;
  }
};

// A libmodbus client connection to the face, for one unit at a time.
class Client {
 public:
  explicit Client(std::uint16_t port) : context_(modbus_new_tcp("127.0.0.1", port)) {
    EXPECT_NE(context_, nullptr);
    modbus_set_response_timeout(context_, 5, 0);
    EXPECT_EQ(modbus_connect(context_), 0) << modbus_strerror(errno);
  }
  ~Client() {
    modbus_close(context_);
    modbus_free(context_);
  }
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  // The registers, or the errno libmodbus set (EMBXGTAR, EMBXILADD, ...).
  std::variant<std::vector<std::uint16_t>, int> read_input(int unit, int address, int count) {
    modbus_set_slave(context_, unit);
    std::vector<std::uint16_t> registers(static_cast<std::size_t>(count));
    if (modbus_read_input_registers(context_, address, count, registers.data()) != count) return errno;
    return registers;
  }
  std::variant<std::vector<std::uint16_t>, int> read_holding(int unit, int address, int count) {
    modbus_set_slave(context_, unit);
    std::vector<std::uint16_t> registers(static_cast<std::size_t>(count));
    if (modbus_read_registers(context_, address, count, registers.data()) != count) return errno;
    return registers;
  }
  int write(int unit, int address, std::uint16_t value) {
    modbus_set_slave(context_, unit);
    return modbus_write_register(context_, address, value) == 1 ? 0 : errno;
  }

 private:
  modbus_t* context_;
};

std::vector<std::uint16_t> registers_of(const std::variant<std::vector<std::uint16_t>, int>& read) {
  if (const int* error = std::get_if<int>(&read)) {
    ADD_FAILURE() << "read failed: " << modbus_strerror(*error);
    return std::vector<std::uint16_t>(modbus::input::count);
  }
  return std::get<std::vector<std::uint16_t>>(read);
}

int error_of(const std::variant<std::vector<std::uint16_t>, int>& read) {
  return std::holds_alternative<int>(read) ? std::get<int>(read) : 0;
}

bool status_has(const std::vector<std::uint16_t>& registers, unsigned bit) {
  return ((registers[modbus::input::status] >> bit) & 1U) != 0;
}

// Asks until `done` holds for the unit's input registers, or 20 s pass.
template <class Done>
std::vector<std::uint16_t> poll_until(Client& client, int unit, Done done) {
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  std::vector<std::uint16_t> registers;
  while (std::chrono::steady_clock::now() < deadline) {
    registers = registers_of(client.read_input(unit, 0, static_cast<int>(modbus::input::count)));
    if (done(registers)) return registers;
    std::this_thread::sleep_for(20ms);  // a PLC's poll interval; the deadline bounds it
  }
  return registers;
}

float float_of(const std::vector<std::uint16_t>& registers, std::uint16_t at) {
  return std::bit_cast<float>(modbus::u32_of_words(registers[at], registers[at + 1], modbus::WordOrder::abcd));
}

// The silo's reading as a PLC reads it is one of the distances the hub holds for it.
TEST(ModbusFace, AUnitsRegistersHoldItsSensorsLatestReading) {
  LiveFace live(false);
  ASSERT_NE(live.port, 0);
  Client client(live.port);
  const auto registers = poll_until(client, 2, [](const auto& r) {
    return status_has(r, modbus::status_bit::valid) && status_has(r, modbus::status_bit::streaming);
  });
  ASSERT_TRUE(status_has(registers, modbus::status_bit::connected));
  ASSERT_TRUE(status_has(registers, modbus::status_bit::valid));
  const float millimetres = float_of(registers, modbus::input::reading_mm);
  const auto micrometres = static_cast<std::int32_t>(
      modbus::u32_of_words(registers[modbus::input::reading_um], registers[2 + 1], modbus::WordOrder::abcd));
  EXPECT_NEAR(millimetres * 1000.0, micrometres, 1.0);
  EXPECT_GT(modbus::u32_of_words(registers[modbus::input::sequence], registers[modbus::input::sequence + 1],
                                 modbus::WordOrder::abcd),
            0U);
  auto latest = live.hub->latest("silo", 4096);
  ASSERT_TRUE(latest.ok());
  bool found = false;
  for (const hub::HubItemPtr& item : *latest) {
    const auto* sample = std::get_if<Sample>(&item->item);
    const auto reading = sample != nullptr ? reading_of(*sample) : std::nullopt;
    if (reading && std::abs(static_cast<float>(reading->value * 1000.0) - millimetres) < 1e-3F) found = true;
  }
  EXPECT_TRUE(found) << millimetres << " mm is none of the silo's readings";
}

TEST(ModbusFace, ExceptionsNameWhatIsWrong) {
  LiveFace live(false);
  ASSERT_NE(live.port, 0);
  Client client(live.port);
  EXPECT_EQ(error_of(client.read_input(99, 0, 1)), EMBXGTAR);    // no sensor is unit 99
  EXPECT_EQ(error_of(client.read_input(2, 40, 10)), EMBXILADD);  // past register 46
  EXPECT_EQ(error_of(client.read_holding(2, 0, 1)), EMBXILFUN);  // read only
  EXPECT_EQ(client.write(2, 0, 3), EMBXILFUN);
  EXPECT_EQ(error_of(client.read_input(2, 0, 1)), 0);  // the connection still serves
}

// A command through the same checks as HTTP: `single` on the ULS, then its outcome; `latch`
// is the LS5's, so the ULS refuses it as a value it does not take.
TEST(ModbusFace, ACommandRunsAndItsOutcomeIsReadBack) {
  LiveFace live(true);
  ASSERT_NE(live.port, 0);
  Client client(live.port);
  poll_until(client, 2, [](const auto& r) { return status_has(r, modbus::status_bit::connected); });
  const auto code = [](std::string_view action) {
    for (const auto& each : modbus::command_codes()) {
      if (each.action == action) return each.code;
    }
    return std::uint16_t{0};
  };
  ASSERT_EQ(client.write(2, modbus::holding::command, code("single")), 0);
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  std::vector<std::uint16_t> holding;
  while (std::chrono::steady_clock::now() < deadline) {
    holding = registers_of(client.read_holding(2, 0, static_cast<int>(modbus::holding::count)));
    if (holding[modbus::holding::command_state] != static_cast<std::uint16_t>(modbus::CommandState::running)) break;
    std::this_thread::sleep_for(20ms);  // polled as a PLC does; the deadline bounds it
  }
  EXPECT_EQ(holding[modbus::holding::command], code("single"));
  EXPECT_EQ(holding[modbus::holding::command_state], static_cast<std::uint16_t>(modbus::CommandState::done));
  EXPECT_EQ(holding[modbus::holding::command_done], 1);
  EXPECT_EQ(client.write(2, modbus::holding::command, code("latch")), EMBXILVAL);
  EXPECT_EQ(client.write(2, modbus::holding::command, 999), EMBXILVAL);
  EXPECT_EQ(client.write(2, modbus::holding::command_state, 0), EMBXILADD);
  EXPECT_EQ(live.face->stats().commands, 1U);
}

// A sensor gone keeps its last value, with connected clear and stale set.
TEST(ModbusFace, ALostSensorKeepsItsLastValueMarkedStale) {
  LiveFace live(false);
  ASSERT_NE(live.port, 0);
  Client client(live.port);
  const auto before = poll_until(client, 1, [](const auto& r) { return status_has(r, modbus::status_bit::valid); });
  ASSERT_TRUE(status_has(before, modbus::status_bit::valid));
  live.site.ls5.kill_hard();
  const auto after = poll_until(client, 1, [](const auto& r) { return !status_has(r, modbus::status_bit::connected); });
  EXPECT_FALSE(status_has(after, modbus::status_bit::connected));
  EXPECT_TRUE(status_has(after, modbus::status_bit::stale));
  EXPECT_FALSE(std::isnan(float_of(after, modbus::input::reading_mm)));
}

int connect_raw(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  EXPECT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
  return fd;
}

// Bytes that are no Modbus close their connection alone; 40 clients polling at once are all
// answered meanwhile.
TEST(ModbusFace, WhatIsNoModbusClosesItsConnectionAndTheOthersAreServed) {
  LiveFace live(false);
  ASSERT_NE(live.port, 0);
  const int hostile = connect_raw(live.port);
  const std::string http = "GET / HTTP/1.1\r\nHost: x\r\n\r\n";
  ASSERT_EQ(::send(hostile, http.data(), http.size(), MSG_NOSIGNAL), static_cast<ssize_t>(http.size()));
  std::array<char, 16> reply{};
  EXPECT_EQ(::recv(hostile, reply.data(), reply.size(), 0), 0);  // closed, nothing answered
  ::close(hostile);
  std::atomic<int> answered{0};
  std::vector<std::thread> clients;
  for (int each = 0; each < 40; ++each) {
    clients.emplace_back([&] {
      Client client(live.port);
      for (int poll = 0; poll < 25; ++poll) {
        if (error_of(client.read_input(1 + poll % 6, 0, 17)) == 0) ++answered;
      }
    });
  }
  for (auto& thread : clients) thread.join();
  EXPECT_EQ(answered.load(), 40 * 25);
  const modbus::FaceStats stats = live.face->stats();
  EXPECT_EQ(stats.malformed, 1U);
  EXPECT_GE(stats.requests, 1000U);
}

TEST(ModbusFace, BeyondLoopbackItNeedsAnAllowListAndItRefusesBadSettings) {
  hub_test::Site site;
  auto hub = hub::Hub::start(site.config);
  modbus::FaceOptions options;
  options.units = {{1, "belt"}};
  options.listen = "0.0.0.0:0";
  auto open = modbus::Face::start(*hub, options);
  ASSERT_FALSE(open.ok());
  EXPECT_NE(open.error().message.find("allow"), std::string::npos) << open.error().message;
  options.listen = "127.0.0.1:0";
  options.word_order = "ABDC";
  EXPECT_FALSE(modbus::Face::start(*hub, options).ok());
  options.word_order = "CDAB";
  options.units = {{1, "belt"}, {1, "silo"}};
  EXPECT_FALSE(modbus::Face::start(*hub, options).ok());
  options.units = {{1, "nope"}};
  EXPECT_FALSE(modbus::Face::start(*hub, options).ok());
}

}  // namespace
