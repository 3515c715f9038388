// The opt-in hardware tier: these tests talk to a real sensor only when its port
// is given in the environment, and skip otherwise (ctest shows them as skipped).
//
//   RANGEKIT_ULS_PORT=/dev/ttyUSB0  [RANGEKIT_ULS_BAUD=115200] [RANGEKIT_ULS_ADDRESS=A]
//   RANGEKIT_LS5_PORT=/dev/ttyUSB1  [RANGEKIT_LS5_BAUD=115200] [RANGEKIT_LS5_ADDRESS=1]
//   RANGEKIT_LS5_UDP=0.0.0.0:5000   (the sensor already sends its UDP stream here)
//   RANGEKIT_HW_WRITE=1             also run the tests that write a setting (each
//                                   restores the value it found; nothing is saved to flash)
//
// Read-only by default, and every test leaves the sensor measuring (or idle) as found.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>

#include "rangekit/core/serial_port.hpp"
#include "rangekit/core/transport.hpp"

namespace hardware_test {

inline std::optional<std::string> env(const char* name) {
  const char* value = std::getenv(name);
  if (value == nullptr || *value == '\0') return std::nullopt;
  return std::string(value);
}

inline std::uint32_t env_baud(const char* name, std::uint32_t fallback) {
  const auto text = env(name);
  return text ? static_cast<std::uint32_t>(std::stoul(*text)) : fallback;
}

// A ULS unit address as `rangekit uls --address` takes it: one character ("A",
// "1" is 0x31), or a number ("0x41", "65").
inline std::optional<std::uint8_t> env_uls_address(const char* name) {
  const auto text = env(name);
  if (!text) return std::nullopt;
  if (text->size() == 1) return static_cast<std::uint8_t>((*text)[0]);
  return static_cast<std::uint8_t>(std::stoul(*text, nullptr, 0));
}

// An LS5 network address, 1-255 (parameter 01).
inline std::uint8_t env_ls5_address(const char* name) {
  const auto text = env(name);
  return text ? static_cast<std::uint8_t>(std::stoul(*text, nullptr, 0)) : std::uint8_t{1};
}

// The port named by `port_variable` at `baud_variable` (factory 115200), 8N1;
// null after a test failure naming the port when it cannot be opened.
inline rangekit::TransportPtr open_port(const char* port_variable, const char* baud_variable) {
  const std::string path = env(port_variable).value_or("");
  const auto baud = env_baud(baud_variable, 115200);
  auto port = rangekit::SerialPort::open(path, rangekit::SerialSettings{baud, rangekit::Parity::none, 1});
  if (!port) {
    ADD_FAILURE() << "cannot open " << path << ": " << port.error().describe();
    return nullptr;
  }
  return std::move(port).value();
}

inline bool writes_allowed() { return env("RANGEKIT_HW_WRITE").value_or("") == "1"; }

}  // namespace hardware_test

// Skips the test (with how to run it) when the variable is not set.
#define RANGEKIT_REQUIRE_ENV(variable)                                                             \
  do {                                                                                             \
    if (!hardware_test::env(variable)) GTEST_SKIP() << "set " variable " to run against a sensor"; \
  } while (false)

#define RANGEKIT_REQUIRE_WRITES()                                                                    \
  do {                                                                                               \
    if (!hardware_test::writes_allowed()) GTEST_SKIP() << "set RANGEKIT_HW_WRITE=1 to allow writes"; \
  } while (false)
