// Drives the LS5 firmware model directly on a virtual time line: bytes in with
// receive(), time with advance(), bytes out with take_line_output().
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "rangekit/ls5/emulator/firmware.hpp"

namespace rangekit::ls5::emulator::testing {

using namespace std::chrono_literals;

inline Scene fixed_scene(double position_mm, double reflectivity = 1.0) {
  Scene scene;
  scene.target = Motion::fixed(position_mm);
  scene.target_set = true;
  scene.reflectivity = reflectivity;
  scene.noise_mm = 0;
  return scene;
}

// Lower boundary 10 mm, range 50 mm: 1 mm is exactly 1000 codes.
inline FirmwareConfig test_config(std::string version = "LS5.12.0") {
  FirmwareConfig config;
  config.lower_boundary_mm = 10;
  config.range_mm = 50;
  config.serial_number = 157;
  config.version_text = std::move(version);
  config.scene = fixed_scene(35);  // code 25000
  return config;
}

inline double position_for_code(double code) { return 10 + code / 1000.0; }

struct Rig {
  std::unique_ptr<Firmware> fw;
  Nanos now{0};
  std::string out;  // every byte that left the line, in order
  std::vector<LineByte> bytes;

  explicit Rig(FirmwareConfig config = test_config()) {
    auto created = Firmware::create(std::move(config));
    EXPECT_TRUE(created) << created.error().message;
    fw = std::move(*created);
  }

  void collect() {
    std::vector<LineByte> taken;
    fw->take_line_output(0, now, taken);
    for (const auto& b : taken) {
      out.push_back(static_cast<char>(b.value));
      bytes.push_back(b);
    }
  }
  void run_to(Nanos when) {
    while (true) {
      const Nanos deadline = fw->next_deadline();
      if (deadline > when) break;
      ASSERT_GE(deadline, now) << "deadline in the past";
      now = deadline;
      fw->advance(now);
      collect();
      ASSERT_GT(fw->next_deadline(), now) << "firmware did not move its deadline";
    }
    now = when;
    fw->advance(now);
    collect();
  }
  void run_for(Nanos span) { run_to(now + span); }
  void send(std::string_view text) {
    for (const char c : text) fw->receive(0, static_cast<std::uint8_t>(c), now);
  }
  // Sends `text`, runs `wait`, returns what came back.
  std::string exchange(std::string_view text, Nanos wait = 20ms) {
    out.clear();
    send(text);
    run_for(wait);
    return out;
  }
  // Writes a parameter and expects its echo.
  void write(std::uint8_t address, std::uint8_t value, std::uint8_t sensor = 1) {
    char text[16];
    std::snprintf(text, sizeof text, "#%02XW%02X%02X\r", sensor, address, value);
    std::string expected = text;
    expected[0] = '!';
    EXPECT_EQ(exchange(text, 2ms), expected);  // 9 bytes: 0.78 ms at 115200
  }
  void set_scene_code(double code) { fw->set_scene(fixed_scene(position_for_code(code))); }
};

inline std::string temp_dir(const std::string& name) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("rangekit-ls5emu-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace rangekit::ls5::emulator::testing
