// The device end of an in-memory loopback pair, scripted by the test: bytes it
// sends are queued for the driver, bytes the driver sent are read with a timeout.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <string>
#include <string_view>

#include "rangekit/core/loopback.hpp"
#include "rangekit/ls5/driver.hpp"

namespace ls5_driver_test {

using namespace std::chrono_literals;

class ScriptedDevice {
 public:
  explicit ScriptedDevice(rangekit::TransportPtr end) : end_(std::move(end)) {}

  void send(std::string_view bytes) { ASSERT_OK(end_->write_all(rangekit::as_bytes(bytes))); }
  // Reads what the driver wrote until `expected` has arrived or `timeout` passed.
  std::string receive_until(std::string_view expected, std::chrono::milliseconds timeout = 5000ms) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (received_.find(expected) == std::string::npos) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) break;
      std::array<std::uint8_t, 256> buffer{};
      auto got = end_->read_some(buffer, left);
      if (!got) break;
      received_.append(reinterpret_cast<const char*>(buffer.data()), *got);
    }
    std::string out;
    const std::size_t at = received_.find(expected);
    if (at == std::string::npos) {
      out.swap(received_);
    } else {
      out = received_.substr(0, at + expected.size());
      received_.erase(0, at + expected.size());
    }
    return out;
  }
  // Everything the driver wrote that arrives within `wait` (nothing expected).
  std::string receive_all(std::chrono::milliseconds wait = 50ms) { return receive_until("\x01never\x01", wait); }
  void close() { end_->close(); }

 private:
  static void ASSERT_OK(const rangekit::Status& status) {
    if (!status) ADD_FAILURE() << status.error().message;
  }
  rangekit::TransportPtr end_;
  std::string received_;
};

// §9.2 identification example: LS5.6.0, lower boundary 8.1234 mm, range 40.001 mm, s/n 157.
inline constexpr std::string_view id_reply_01 = "%01LS5.6.0   b8,1234d40,0010s/n0000157\r";

struct Rig {
  ScriptedDevice device;
  rangekit::ls5::Driver driver;
};

inline rangekit::ls5::DriverOptions fast_options(std::uint8_t address = 0x01) {
  rangekit::ls5::DriverOptions options;
  options.address = address;
  options.timeout = 300ms;  // replies are already queued when they are expected
  return options;
}

}  // namespace ls5_driver_test
