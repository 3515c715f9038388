// Fault injection and outputs through the control socket of `rangekit sim uls` on the
// virtual clock: bit errors, dropped bytes, no return, power cycle, pointer/laser outputs.
// One emulator process per test; a host on the configuration port's pty.
#include <gtest/gtest.h>
#include "build_paths.hpp"
#include "child_process.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <bitset>
#include <filesystem>

#include "rangekit/core/serial_port.hpp"
#include "rangekit/sim/control_socket.hpp"

namespace rangekit {
namespace {

using namespace std::chrono_literals;

class SimUls {
 public:
  explicit SimUls(const std::string& name, const std::string& extra = "") {
    dir_ = std::filesystem::temp_directory_path() / ("rangekit-ulsfault-" + name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    config_ = (dir_ / "config").string();
    control_path_ = (dir_ / "control").string();
    const std::string command = std::string(rangekit::test::cli_path()) + " sim uls --config-port " + config_ +
                                " --virtual-clock --seed 5 --control " + control_path_ + " " + extra;
    int fds[2];
    EXPECT_EQ(::pipe(fds), 0);
    child_ = rangekit::test::fork_child();
    if (child_ == 0) {
      ::dup2(fds[1], STDOUT_FILENO);
      ::close(fds[0]);
      ::execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(fds[1]);
    std::string ready;  // wait for the ready line instead of sleeping
    char c = 0;
    while (::read(fds[0], &c, 1) == 1 && c != '\n') ready.push_back(c);
    ready_pipe_ = fds[0];
    EXPECT_NE(ready.find("ready"), std::string::npos) << ready;
    auto host = SerialPort::open(config_, SerialSettings{115200, Parity::none, 1});
    EXPECT_TRUE(host) << host.error().message;
    if (host) host_ = std::move(*host);
    auto client = ControlClient::connect(control_path_);
    EXPECT_TRUE(client) << client.error().message;
    if (client) control_ = std::make_unique<ControlClient>(std::move(*client));
  }
  ~SimUls() {
    host_.reset();
    control_.reset();
    rangekit::test::end_child(child_);
    ::close(ready_pipe_);
    std::filesystem::remove_all(dir_);
  }
  SimUls(const SimUls&) = delete;
  SimUls& operator=(const SimUls&) = delete;

  nlohmann::json request(const nlohmann::json& body) {
    auto reply = control_->request(body);
    EXPECT_TRUE(reply) << body.dump();
    return reply ? *reply : nlohmann::json{};
  }
  void advance(double seconds) {
    const auto reply = request({{"cmd", "advance"}, {"seconds", seconds}});
    EXPECT_EQ(reply.value("ok", false), true) << reply.dump();
  }
  // Writes `text`, runs `seconds` of virtual time and returns every byte the host got.
  std::string exchange(std::string_view text, double seconds = 0.05) {
    EXPECT_TRUE(host_->write_all(as_bytes(text)));
    // The runtime reads the pty on its next pass; a status request is one pass.
    (void)request({{"cmd", "status"}});
    advance(seconds);
    return read_all();
  }
  std::string read_all() {
    std::string text;
    std::array<std::uint8_t, 4096> buffer{};
    while (true) {
      auto got = host_->read_some(buffer, 200ms);
      if (!got || *got == 0) break;
      text.append(reinterpret_cast<const char*>(buffer.data()), *got);
    }
    return text;
  }
  [[nodiscard]] std::string state_dir() const { return (dir_ / "state").string(); }

 private:
  std::filesystem::path dir_;
  std::string config_;
  std::string control_path_;
  pid_t child_ = -1;
  int ready_pipe_ = -1;
  std::unique_ptr<SerialPort> host_;
  std::unique_ptr<ControlClient> control_;
};

std::string repeat(std::string_view text, std::size_t times) {
  std::string out;
  for (std::size_t i = 0; i < times; ++i) out += text;
  return out;
}

TEST(UlsFaults, LineNoiseFlipsBitsAtTheRequestedRate) {
  SimUls sim("noise");
  EXPECT_EQ(sim.exchange("$MM\r"), "$MM,1\r");  // clean line first
  const auto reply = sim.request({{"cmd", "noise"}, {"line", "configuration"}, {"bit_error_rate", 0.05}});
  ASSERT_EQ(reply.value("ok", false), true) << reply.dump();
  const std::string expected = repeat("$MM,1\r", 200);
  const std::string got = sim.exchange(repeat("$MM\r", 200), 0.5);  // 1200 characters: 120 ms
  ASSERT_EQ(got.size(), expected.size());                           // bit errors only: nothing lost
  std::size_t flipped = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    flipped += std::bitset<8>(static_cast<unsigned char>(got[i] ^ expected[i])).count();
  }
  // 9600 bits at 5%: 480 expected, sigma 21; a wide band keeps the test about the rate.
  EXPECT_GT(flipped, 380U);
  EXPECT_LT(flipped, 580U);
  (void)sim.request({{"cmd", "noise"}, {"line", "configuration"}, {"bit_error_rate", 0.0}});
  EXPECT_EQ(sim.exchange("$MM\r"), "$MM,1\r");  // and clean again
}

TEST(UlsFaults, DroppedBytesAtTheRequestedRate) {
  SimUls sim("drop");
  const auto reply = sim.request({{"cmd", "noise"}, {"line", "configuration"}, {"drop_rate", 0.25}});
  ASSERT_EQ(reply.value("ok", false), true) << reply.dump();
  const std::string got = sim.exchange(repeat("$MM\r", 200), 0.5);
  // 1200 bytes sent, a quarter lost: 900 expected, sigma 15.
  EXPECT_GT(got.size(), 840U);
  EXPECT_LT(got.size(), 960U);
  for (const char c : got) EXPECT_NE(std::string_view("$MM,1\r").find(c), std::string_view::npos);  // no bit errors
}

TEST(UlsFaults, NoReturnGivesTargetNotFoundAndTheFaultCurrent) {
  SimUls sim("noreturn");
  EXPECT_EQ(sim.exchange("$DM,1\r$CL,1\r$AH,100\r$AT,1\r$PF,5000\r$GO\r"), "$OK\r$OK\r$OK\r$OK\r$OK\r$OK\r");
  const std::string measuring = sim.exchange("", 1.0);
  EXPECT_NE(measuring.find("$BM,50.0"), std::string::npos) << measuring;
  EXPECT_NEAR(sim.request({{"cmd", "outputs"}})["current_ma"].get<double>(), 12.0, 0.01);  // 50 m of 0-100 m
  auto reply = sim.request({{"cmd", "fault"}, {"kind", "no_return"}, {"on", true}});
  ASSERT_EQ(reply.value("ok", false), true) << reply.dump();
  const std::string lost = sim.exchange("", 0.5);
  EXPECT_NE(lost.find("$ER,4\r"), std::string::npos) << lost;
  EXPECT_EQ(lost.find("$BM"), std::string::npos) << lost;
  auto outputs = sim.request({{"cmd", "outputs"}});
  EXPECT_EQ(outputs["last_error"], 4);
  EXPECT_NEAR(outputs["current_ma"].get<double>(), 12.0, 0.01);  // held until AT = 1 s
  (void)sim.exchange("", 1.0);
  EXPECT_DOUBLE_EQ(sim.request({{"cmd", "outputs"}})["current_ma"].get<double>(), 3.0);  // AF (§6)
  reply = sim.request({{"cmd", "fault"}, {"kind", "no_return"}, {"on", false}});
  ASSERT_EQ(reply.value("ok", false), true);
  const std::string back = sim.exchange("", 1.0);
  EXPECT_NE(back.find("$BM,50.0"), std::string::npos) << back;
  reply = sim.request({{"cmd", "fault"}, {"kind", "lightning"}});
  EXPECT_TRUE(reply.contains("error"));
}

TEST(UlsFaults, PowerCycleKeepsOnlyWhatWasSaved) {
  SimUls sim("power", "--state " + std::string(std::filesystem::temp_directory_path() /
                                               ("rangekit-ulsfault-state-" + std::to_string(::getpid()))));
  EXPECT_EQ(sim.exchange("$PF,100\r$PA,1\r$SU\r$PO,2000\r$MA,1\r"), "$OK\r$OK\r$OK\r$OK\r$OK\r");
  auto reply = sim.request({{"cmd", "power_cycle"}});
  ASSERT_EQ(reply.value("ok", false), true) << reply.dump();
  EXPECT_EQ(sim.exchange("$PF\r$PO\r$MA\r"), "$PF,100,2000,2000\r$PO,1024,1024\r$MA,0\r");  // PO, MA not saved
  auto outputs = sim.request({{"cmd", "outputs"}});
  EXPECT_EQ(outputs["pointer"], true);  // PA saved: pointer on at power-up
  EXPECT_EQ(outputs["measuring"], false);
  // Autostart saved this time: the unit measures after the next power cycle.
  EXPECT_EQ(sim.exchange("$MA,1\r$SU\r"), "$OK\r$OK\r");
  (void)sim.request({{"cmd", "power_cycle"}});
  outputs = sim.request({{"cmd", "outputs"}});
  EXPECT_EQ(outputs["measuring"], true);
  EXPECT_EQ(outputs["laser_firing"], true);
  std::filesystem::remove_all(std::filesystem::temp_directory_path() /
                              ("rangekit-ulsfault-state-" + std::to_string(::getpid())));
}

// docs/conformance.md U122. §8 "Save User Settings into Non-Volatile Memory"; §1 "each time
// you turn on the ULS, it will use these same settings": no --state file, one run.
TEST(UlsFaults, SavedSettingsSurviveAPowerCycleWithoutAStateFileU122) {
  SimUls sim("nvm");
  EXPECT_EQ(sim.exchange("$PO,2000\r$SU\r$PF,100\r"), "$OK\r$OK\r$OK\r");
  auto reply = sim.request({{"cmd", "power_cycle"}});
  ASSERT_EQ(reply.value("ok", false), true) << reply.dump();
  // PO saved (factory 1024); PF set after SU is not (factory 2000).
  EXPECT_EQ(sim.exchange("$PO\r$PF\r"), "$PO,2000,1024\r$PF,2000,2000,2000\r");
}

// docs/conformance.md U45
TEST(UlsFaults, PointerAndLaserOutputsOnTheControlSocket) {
  SimUls sim("pointer");
  auto outputs = sim.request({{"cmd", "outputs"}});
  EXPECT_EQ(outputs["pointer"], false);
  EXPECT_EQ(outputs["laser_firing"], false);
  EXPECT_EQ(sim.exchange("$PT,1\r"), "$OK\r");
  outputs = sim.request({{"cmd", "outputs"}, {"device", 0}});
  EXPECT_EQ(outputs["pointer"], true);
  EXPECT_EQ(outputs["laser_firing"], false);
  EXPECT_EQ(outputs["status"], 1);
  EXPECT_EQ(sim.exchange("$CO,0\r$GO\r"), "$OK\r$OK\r");
  outputs = sim.request({{"cmd", "outputs"}});
  EXPECT_EQ(outputs["laser_firing"], true);
  EXPECT_EQ(outputs["status"], 7);
  EXPECT_EQ(sim.exchange("$PT,0\r$ST\r"), "$OK\r$OK\r");
  outputs = sim.request({{"cmd", "outputs"}});
  EXPECT_EQ(outputs["pointer"], false);
  EXPECT_EQ(outputs["laser_firing"], false);
}

}  // namespace
}  // namespace rangekit
