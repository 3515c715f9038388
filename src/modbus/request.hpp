// Modbus TCP requests, without I/O: the MBAP framer finds each request in a connection's
// bytes, and answer_request() writes its response from the units' registers. The server
// and the fuzzer call the same two functions.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "modbus/register_map.hpp"
#include "modbus/unit_state.hpp"
#include "rangekit/core/framer.hpp"

namespace rangekit::modbus {

// Exception codes (Modbus Application Protocol v1.1b3, §7).
namespace exception {
inline constexpr std::uint8_t illegal_function = 0x01;
inline constexpr std::uint8_t illegal_address = 0x02;
inline constexpr std::uint8_t illegal_value = 0x03;
inline constexpr std::uint8_t busy = 0x06;
inline constexpr std::uint8_t gateway_target_failed = 0x0B;
}  // namespace exception

inline constexpr std::size_t mbap_header_size = 7;                   // transaction, protocol, length, unit
inline constexpr std::size_t max_adu_size = mbap_header_size + 253;  // the PDU is at most 253 bytes

// One request: the MBAP header's length says where it ends. A protocol id other than 0 or a
// length out of 2-254 is not Modbus: the connection cannot find the next request, so it closes.
FrameScan scan_mbap_frame(Bytes buffer) noexcept;

using HoldingImage = std::array<std::uint16_t, holding::count>;

// What a request reaches: the face's units.
class UnitTable {
 public:
  UnitTable() = default;
  UnitTable(const UnitTable&) = delete;
  UnitTable& operator=(const UnitTable&) = delete;
  virtual ~UnitTable() = default;
  [[nodiscard]] virtual bool has_unit(std::uint8_t unit) const = 0;
  [[nodiscard]] virtual InputImage input_registers(std::uint8_t unit) const = 0;
  [[nodiscard]] virtual bool writable() const = 0;
  [[nodiscard]] virtual HoldingImage holding_registers(std::uint8_t unit) const = 0;
  // A command code written to the command register: 0 when taken, else the exception to answer.
  virtual std::uint8_t command(std::uint8_t unit, std::uint16_t code) = 0;
};

// Appends the response to `frame` (a complete request from scan_mbap_frame) to `out`, and
// returns the exception code it carries, 0 for none.
std::uint8_t answer_request(Bytes frame, UnitTable& units, std::vector<std::uint8_t>& out);

}  // namespace rangekit::modbus
