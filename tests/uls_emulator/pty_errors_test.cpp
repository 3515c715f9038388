// Every §10 error a host can provoke with §8 commands, through `rangekit sim uls`
// on a real pty, as a terminal user would see it. Expected numbers are typed
// from §10 of uls-interface-spec.txt.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "ls5_driver/cli_process.hpp"
#include "rangekit/core/serial_port.hpp"

namespace {

using ls5_driver_test::Child;

struct Terminal {
  std::unique_ptr<rangekit::SerialPort> port;

  // Sends one command and returns the next line (without its CR); "" on timeout.
  std::string ask(const std::string& command) {
    const std::string frame = command + "\r";
    if (!port->write_all(rangekit::as_bytes(frame))) return "<write failed>";
    return next_line();
  }
  std::string next_line() {
    std::string line;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (std::chrono::steady_clock::now() < deadline) {
      std::uint8_t byte = 0;
      auto got = port->read_some({&byte, 1}, std::chrono::milliseconds(200));
      if (!got || *got == 0) continue;
      if (byte == '\r') return line;
      line.push_back(static_cast<char>(byte));
    }
    return line;
  }
};

struct Sim {
  std::filesystem::path dir;
  std::unique_ptr<Child> child;
  Terminal config;

  explicit Sim(const std::string& scene) {
    std::string pattern = (std::filesystem::temp_directory_path() / "rangekit-ulserr-XXXXXX").string();
    dir = ::mkdtemp(pattern.data());
    std::vector<std::string> arguments{
        "sim", "uls", "--port", (dir / "uls").string(), "--config-port", (dir / "uls-config").string()};
    if (!scene.empty()) {
      std::ofstream(dir / "scene.toml") << scene;
      arguments.push_back("--scene");
      arguments.push_back((dir / "scene.toml").string());
    }
    child = std::make_unique<Child>(arguments);
    if (child->read_line().find("ready:") == std::string::npos) return;
    auto opened = rangekit::SerialPort::open((dir / "uls-config").string(), rangekit::SerialSettings{});
    if (opened) config.port = std::move(opened).value();
  }
  ~Sim() {
    config.port.reset();
    child.reset();
    std::filesystem::remove_all(dir);
  }
};

TEST(UlsPtyErrors, EveryCommandErrorOfSection10) {
  Sim sim("");
  ASSERT_TRUE(sim.config.port);
  EXPECT_EQ(sim.config.ask("$XY"), "$ER,1");          // 1 General Command Interface Error
  EXPECT_EQ(sim.config.ask("$UA"), "$ER,82");         // 82 Unit Address Not Assigned
  EXPECT_EQ(sim.config.ask("$PF,5001"), "$ER,32");    // 32 Invalid Rep Rate (10-5000)
  EXPECT_EQ(sim.config.ask("$BR,0,1234"), "$ER,34");  // 34 Invalid Baud Rate
  EXPECT_EQ(sim.config.ask("$AW,0"), "$ER,35");       // 35 Invalid Average Weight
  EXPECT_EQ(sim.config.ask("$PO,992"), "$ER,49");     // 49 PPM must be greater than AW (992)
  EXPECT_EQ(sim.config.ask("$AL,10"), "$ER,83");      // 83 Invalid MA420 Range (AL = AH)
  EXPECT_EQ(sim.config.ask("$MO,3"), "$ER,84");       // 84 Invalid Port
  EXPECT_EQ(sim.config.ask("$MM,4"), "$ER,85");       // 85 Invalid Measurement Mode
  EXPECT_EQ(sim.config.ask("$ST"), "$ER,86");         // 86 Instrument Not Measuring
  EXPECT_EQ(sim.config.ask("$GO"), "$OK");
  EXPECT_EQ(sim.config.ask("$MM,2"), "$ER,31");  // 31 No Serial While Measuring (U24)
}

TEST(UlsPtyErrors, TargetNotFoundIsStreamed) {
  // 4 Lock Not Found: a gray target far beyond the 133 m of §9 answers nothing.
  Sim sim("[[targets]]\ndistance_m = 3000\nreflectivity = 0.2\n");
  ASSERT_TRUE(sim.config.port);
  EXPECT_EQ(sim.config.ask("$GO"), "$OK");
  EXPECT_EQ(sim.config.next_line(), "$ER,4");
}

TEST(UlsPtyErrors, AverageNotFilledIsStreamed) {
  // 5 Average Weight Not Filled: dust spoils half the pulses, so 992 good ones
  // out of 1024 (factory AW/PPM) never come together.
  Sim sim("dust = 0.5\nambient_noise = 0\n[[targets]]\ndistance_m = 30\n");
  ASSERT_TRUE(sim.config.port);
  EXPECT_EQ(sim.config.ask("$GO"), "$OK");
  EXPECT_EQ(sim.config.next_line(), "$ER,5");
}

// Each measurement mode over the pty, in the §8/§9 line forms (U10, U13).
TEST(UlsPtyErrors, EachModeStreamsItsLineForm) {
  Sim sim("[[targets]]\ndistance_m = 12.5\n");
  ASSERT_TRUE(sim.config.port);
  EXPECT_EQ(sim.config.ask("$PF,5000"), "$OK");
  EXPECT_EQ(sim.config.ask("$GO"), "$OK");  // averaging (factory, MM 1)
  const auto averaging = sim.config.next_line();
  EXPECT_TRUE(std::regex_match(averaging, std::regex(R"(\$BM,12\.[45]\d\d(,\d+)?)"))) << averaging;
  EXPECT_EQ(sim.config.ask("$ST"), "$OK");
  EXPECT_EQ(sim.config.ask("$MM,2"), "$OK");  // binning: $BM,i,m,n,s
  EXPECT_EQ(sim.config.ask("$GO"), "$OK");
  const auto binning = sim.config.next_line();
  EXPECT_TRUE(std::regex_match(binning, std::regex(R"(\$BM,0,\d+,\d+\.\d{3},\d+)"))) << binning;
}

TEST(UlsPtyErrors, LookDownReportsATargetComingCloser) {
  // Look down references the distance at GO and reports $BM,1 once something is
  // nearer than the trip point (0.2 m factory) for 30 pulses (§3): an approaching target.
  Sim sim("[[targets]]\ndistance_m = 12.5\nspeed_mps = -1.0\n");
  ASSERT_TRUE(sim.config.port);
  EXPECT_EQ(sim.config.ask("$MM,3"), "$OK");
  EXPECT_EQ(sim.config.ask("$GO"), "$OK");
  const auto look_down = sim.config.next_line();
  EXPECT_TRUE(std::regex_match(look_down, std::regex(R"(\$BM,[01])"))) << look_down;
}

}  // namespace
