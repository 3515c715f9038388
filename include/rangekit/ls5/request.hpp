// Requests host -> sensor: '#' AA command [arguments] CR (table 9.1, L3).
#pragma once

#include <cstdint>

#include "rangekit/core/framer.hpp"
#include "rangekit/core/result.hpp"
#include "rangekit/ls5/commands.hpp"
#include "rangekit/ls5/frame.hpp"

namespace rangekit::ls5 {

struct Request {
  std::uint8_t address = 0x01;  // 00 broadcast, 01-FF a sensor
  CommandId command = CommandId::identification;
  std::uint8_t parameter = 0;  // R and W
  std::uint8_t value = 0;      // W

  static constexpr Request simple(std::uint8_t address, CommandId command) noexcept {
    return Request{address, command, 0, 0};
  }
  static constexpr Request read(std::uint8_t address, std::uint8_t parameter) noexcept {
    return Request{address, CommandId::read_parameter, parameter, 0};
  }
  static constexpr Request write(std::uint8_t address, std::uint8_t parameter, std::uint8_t value) noexcept {
    return Request{address, CommandId::write_parameter, parameter, value};
  }
  [[nodiscard]] constexpr bool is_broadcast() const noexcept { return address == broadcast_address; }
  // A sensor answers unless the request is a broadcast (table 9.1 note 2).
  [[nodiscard]] bool expects_reply() const noexcept;
  friend constexpr bool operator==(const Request&, const Request&) = default;
};

// Parses a frame as scan_request_frame hands it out: '#' up to, not including, CR.
// Only the frame's syntax is checked; whether the parameter exists or accepts the
// value is check_parameter_byte's job (conformance L14).
Result<Request> parse_request(Bytes frame);
// Parses exactly one frame with its CR and nothing around it.
Result<Request> parse_request_line(Bytes line);
// Writes "#AA<cmd>[args]\r" with upper-case hex.
Result<FrameText> encode_request(const Request& request);

}  // namespace rangekit::ls5
