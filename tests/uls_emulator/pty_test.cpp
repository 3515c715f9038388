// The ULS model over real pseudo-terminals: a command session through the
// `rangekit sim uls` binary, and an 8-unit bus and a baud change through the
// runtime on the virtual clock.
#include <gtest/gtest.h>
#include "build_paths.hpp"
#include "child_process.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <cstdio>
#include <filesystem>

#include "rangekit/core/serial_port.hpp"
#include "rangekit/sim/control_socket.hpp"
#include "rangekit/sim/emulator_runtime.hpp"
#include "rangekit/uls/emulator/firmware.hpp"

namespace rangekit::uls::emulator {
namespace {

using namespace std::chrono_literals;

// Reads until `lines` CRs arrived or nothing came for `quiet`.
std::string read_lines(Transport& port, std::size_t lines, std::chrono::milliseconds quiet = 500ms) {
  std::string text;
  std::array<std::uint8_t, 256> buffer{};
  while (static_cast<std::size_t>(std::count(text.begin(), text.end(), '\r')) < lines) {
    auto got = port.read_some(buffer, quiet);
    if (!got || *got == 0) break;
    text.append(reinterpret_cast<const char*>(buffer.data()), *got);
  }
  return text;
}

struct Bus {
  std::vector<std::unique_ptr<Firmware>> units;
  std::unique_ptr<EmulatorRuntime> runtime;
  std::unique_ptr<SerialPort> host;

  // Sends a command, lets the virtual clock run 20 ms, reads the reply lines.
  std::string ask(std::string_view command, std::size_t lines = 1) {
    EXPECT_TRUE(host->write_all(as_bytes(command)));
    EXPECT_TRUE(host->write_all(as_bytes("\r")));
    EXPECT_TRUE(runtime->step(0ns));
    // At 9600 baud a 6-byte request, the 1 ms turnaround and an 11-byte reply take 20.5 ms (U19, U133).
    EXPECT_TRUE(runtime->advance_to(runtime->now() + 40ms));
    return read_lines(*host, lines, lines == 0 ? 50ms : 500ms);
  }
};

Bus make_bus(std::vector<std::optional<std::uint8_t>> addresses) {
  Bus bus;
  LineConfig line{"bus", std::nullopt, {}};
  std::uint32_t seed = 1;
  for (const auto address : addresses) {
    FirmwareOptions options;
    options.address = address;
    options.seed = seed++;
    bus.units.push_back(std::make_unique<Firmware>(std::move(options)));
    line.attachments.push_back(LineAttachment{bus.units.back().get(), universal_port});
  }
  RuntimeOptions runtime_options;
  runtime_options.virtual_clock = true;
  auto runtime = EmulatorRuntime::create({line}, runtime_options);
  EXPECT_TRUE(runtime) << runtime.error().message;
  bus.runtime = std::move(*runtime);
  auto host = SerialPort::open(bus.runtime->line_path(0), SerialSettings{115200, Parity::none, 1});
  EXPECT_TRUE(host) << host.error().message;
  bus.host = std::move(*host);
  return bus;
}

// docs/conformance.md U37
TEST(UlsPty, BusOfEightUnitsWithAddressAssignment) {
  const std::string addresses = "ABCDEFGH";
  std::vector<std::optional<std::uint8_t>> list;
  for (const char c : addresses) list.emplace_back(static_cast<std::uint8_t>(c));
  auto bus = make_bus(list);
  for (const char c : addresses) {
    const std::string a(1, c);
    EXPECT_EQ(bus.ask("#" + a + "UA"), "#" + a + "UA," + std::to_string(static_cast<int>(c)) + "\r");
  }
  // Re-address unit C as 'z'; only that unit answers at either address afterwards.
  EXPECT_EQ(bus.ask("#CUA,z"), "#COK\r");
  EXPECT_EQ(bus.ask("#CMM", 0), "");
  EXPECT_EQ(bus.ask("#zMM"), "#zMM,1\r");
  // Broadcast: every unit acts, nobody answers.
  EXPECT_EQ(bus.ask("#\xF5MM,2", 0), "");
  for (const char c : std::string("ABDEFGHz")) {
    const std::string a(1, c);
    EXPECT_EQ(bus.ask("#" + a + "MM"), "#" + a + "MM,2\r");
  }
  // Two units given the same address answer together and collide on the wire.
  EXPECT_EQ(bus.ask("#AUA,B"), "#AOK\r");
  const std::string collided = bus.ask("#BMM");
  EXPECT_NE(collided, "#BMM,2\r");
}

// U127: §8 "$ = non-addressable protocol message identifier": every unit on the line takes a `$`
// request and answers it, and on one RS-485 pair the two answers collide.
TEST(UlsPty, DollarRequestsOnABusAreAnsweredByEveryUnitAndCollide) {
  auto bus = make_bus({static_cast<std::uint8_t>('A'), static_cast<std::uint8_t>('B')});
  EXPECT_NE(bus.ask("$MM"), "$MM,1\r");
  EXPECT_EQ(bus.ask("#AMM"), "#AMM,1\r");  // addressed: one answer, clean
}

TEST(UlsPty, FactoryUnitsIgnoreAddressedFrames) {
  auto bus = make_bus({std::nullopt});
  EXPECT_EQ(bus.ask("#0MM", 0), "");
  EXPECT_EQ(bus.ask("$UA"), "$ER,82\r");
  EXPECT_EQ(bus.ask("$UA,K"), "$OK\r");  // installation: program the address
  EXPECT_EQ(bus.ask("#KUA"), "#KUA,75\r");
}

// docs/conformance.md U36
TEST(UlsPty, BaudChangeMidSessionNeedsTheHostToFollow) {
  auto bus = make_bus({std::nullopt});
  EXPECT_EQ(bus.ask("$BR,1,9600"), "$OK\r");
  // The host still at 115200 now sees garbage.
  const std::string garbled = bus.ask("$MM");
  EXPECT_NE(garbled, "$MM,1\r");
  ASSERT_TRUE(bus.host->reconfigure(SerialSettings{9600, Parity::none, 1}));
  EXPECT_EQ(bus.ask("$MM"), "$MM,1\r");
  EXPECT_EQ(bus.ask("$BR,1"), "$BR,1,9600\r");
}

TEST(UlsPty, CommandSessionThroughTheCli) {
  const auto dir = std::filesystem::temp_directory_path() / ("rangekit-simuls-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string port = (dir / "uls").string();
  const std::string config = (dir / "uls-config").string();
  const std::string control = (dir / "control").string();
  const std::string command = std::string(rangekit::test::cli_path()) + " sim uls --port " + port + " --config-port " +
                              config + " --control " + control;
  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);
  const pid_t child = rangekit::test::fork_child();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::dup2(pipe_fds[1], STDOUT_FILENO);
    ::close(pipe_fds[0]);
    ::execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(pipe_fds[1]);
  // Wait for the ready line instead of sleeping.
  std::string ready;
  char c = 0;
  while (::read(pipe_fds[0], &c, 1) == 1 && c != '\n') ready.push_back(c);
  EXPECT_NE(ready.find("ready"), std::string::npos) << ready;
  {
    auto host = SerialPort::open(config, SerialSettings{115200, Parity::none, 1});
    ASSERT_TRUE(host) << host.error().message;
    ASSERT_TRUE((*host)->write_all(as_bytes("$ID\r$MM\r$PF,9\r$DM,1\r$GO\r")));
    const std::string replies = read_lines(**host, 6, 2000ms);
    EXPECT_EQ(replies.substr(0, 4), "$ID,") << replies;
    const std::string expected_replies = "\r$MM,1\r$ER,32\r$OK\r$OK\r$BM,";
    const auto at = replies.find(expected_replies);
    ASSERT_NE(at, std::string::npos) << replies;
    EXPECT_NEAR(std::stod(replies.substr(at + expected_replies.size())), 50.0, 0.04) << replies;
    auto client = ControlClient::connect(control);
    ASSERT_TRUE(client) << client.error().message;
    auto moved = client->request({{"cmd", "move_target"}, {"device", 0}, {"distance_m", 20.0}});
    ASSERT_TRUE(moved);
    EXPECT_EQ((*moved)["ok"], true) << moved->dump();
    // Within a few 0.512 s cycles the unit reports the moved target.
    const std::string after = read_lines(**host, 4, 3000ms);
    EXPECT_TRUE(after.find("$BM,20.0") != std::string::npos || after.find("$BM,19.9") != std::string::npos) << after;
    auto outputs = client->request({{"cmd", "outputs"}});
    ASSERT_TRUE(outputs);
    EXPECT_EQ((*outputs)["measuring"], true) << outputs->dump();
    EXPECT_EQ((*outputs)["status"], 7) << outputs->dump();
    auto unknown = client->request({{"cmd", "outputs"}, {"device", "Q"}});
    ASSERT_TRUE(unknown);
    EXPECT_TRUE(unknown->contains("error")) << unknown->dump();
    ASSERT_TRUE((*host)->write_all(as_bytes("$ST\r")));
  }
  const int status = rangekit::test::end_child(child);
  ::close(pipe_fds[0]);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  EXPECT_FALSE(std::filesystem::exists(port));  // symlinks removed on SIGTERM
  EXPECT_FALSE(std::filesystem::exists(config));
  std::filesystem::remove_all(dir);
}

TEST(UlsPty, CliRefusesAnExistingPath) {
  const auto path = std::filesystem::temp_directory_path() / ("rangekit-simuls-busy-" + std::to_string(::getpid()));
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    std::fclose(f);
  }
  const std::string command = std::string(rangekit::test::cli_path()) + " sim uls --port " + path.string() + " 2>&1";
  std::FILE* out = ::popen(command.c_str(), "r");
  ASSERT_NE(out, nullptr);
  std::string text;
  std::array<char, 256> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), out) != nullptr) text += buffer.data();
  const int status = ::pclose(out);
  EXPECT_NE(status, 0);
  EXPECT_NE(text.find("already exists"), std::string::npos) << text;
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace rangekit::uls::emulator
