#include "modbus/request.hpp"

namespace rangekit::modbus {
namespace {

constexpr std::uint8_t read_holding = 0x03;
constexpr std::uint8_t read_input = 0x04;
constexpr std::uint8_t write_single = 0x06;
constexpr std::uint8_t write_multiple = 0x10;
constexpr std::size_t max_read = 125;   // registers one read may ask for
constexpr std::size_t max_write = 123;  // registers one write-multiple may carry

std::uint16_t u16_at(Bytes bytes, std::size_t at) {
  return static_cast<std::uint16_t>((bytes[at] << 8) | bytes[at + 1]);
}

void put_u16(std::vector<std::uint8_t>& out, std::uint16_t value) {
  out.push_back(static_cast<std::uint8_t>(value >> 8));
  out.push_back(static_cast<std::uint8_t>(value & 0xFF));
}

// The response's MBAP header (the request's transaction and unit), then `pdu`.
void respond(Bytes request, std::span<const std::uint8_t> pdu, std::vector<std::uint8_t>& out) {
  out.insert(out.end(), request.begin(), request.begin() + 4);  // transaction id, protocol id
  put_u16(out, static_cast<std::uint16_t>(pdu.size() + 1));
  out.push_back(request[6]);
  out.insert(out.end(), pdu.begin(), pdu.end());
}

std::uint8_t refuse(Bytes request, std::uint8_t function, std::uint8_t code, std::vector<std::uint8_t>& out) {
  const std::array<std::uint8_t, 2> pdu{static_cast<std::uint8_t>(function | 0x80U), code};
  respond(request, pdu, out);
  return code;
}

template <std::size_t N>
std::uint8_t answer_read(Bytes request, Bytes pdu, const std::array<std::uint16_t, N>& image,
                         std::vector<std::uint8_t>& out) {
  const std::uint8_t function = pdu[0];
  if (pdu.size() != 5) return refuse(request, function, exception::illegal_value, out);
  const std::size_t address = u16_at(pdu, 1);
  const std::size_t count = u16_at(pdu, 3);
  if (count == 0 || count > max_read) return refuse(request, function, exception::illegal_value, out);
  if (address + count > N) return refuse(request, function, exception::illegal_address, out);
  std::vector<std::uint8_t> reply{function, static_cast<std::uint8_t>(2 * count)};
  reply.reserve(2 + 2 * count);
  for (std::size_t at = address; at < address + count; ++at) put_u16(reply, image[at]);
  respond(request, reply, out);
  return 0;
}

// Writes reach the command register alone; the others are read back only.
std::uint8_t answer_write(Bytes request, Bytes pdu, UnitTable& units, std::vector<std::uint8_t>& out) {
  const std::uint8_t function = pdu[0];
  std::size_t address = 0;
  std::size_t count = 1;
  std::uint16_t value = 0;
  if (function == write_single) {
    if (pdu.size() != 5) return refuse(request, function, exception::illegal_value, out);
    address = u16_at(pdu, 1);
    value = u16_at(pdu, 3);
  } else {
    if (pdu.size() < 6) return refuse(request, function, exception::illegal_value, out);
    address = u16_at(pdu, 1);
    count = u16_at(pdu, 3);
    if (count == 0 || count > max_write || pdu[5] != 2 * count || pdu.size() != 6 + 2 * count) {
      return refuse(request, function, exception::illegal_value, out);
    }
    value = u16_at(pdu, 6);
  }
  if (address != holding::command || count != 1) return refuse(request, function, exception::illegal_address, out);
  if (const std::uint8_t refused = units.command(request[6], value); refused != 0) {
    return refuse(request, function, refused, out);
  }
  // Both echo the address and, for 06, the value; 16 answers its address and count.
  respond(request, pdu.first(5), out);
  return 0;
}

}  // namespace

FrameScan scan_mbap_frame(Bytes buffer) noexcept {
  if (buffer.size() < mbap_header_size) return FrameScan::need_more();
  if (u16_at(buffer, 2) != 0) return FrameScan::invalid(buffer.size(), "MBAP protocol id is not 0: not Modbus TCP");
  const std::size_t length = u16_at(buffer, 4);
  if (length < 2 || length > max_adu_size - 6) {
    return FrameScan::invalid(buffer.size(), "MBAP length is not 2-254: not a Modbus TCP request");
  }
  if (buffer.size() < 6 + length) return FrameScan::need_more();
  return FrameScan::complete(buffer.first(6 + length), 6 + length);
}

std::uint8_t answer_request(Bytes frame, UnitTable& units, std::vector<std::uint8_t>& out) {
  const Bytes pdu = frame.subspan(mbap_header_size);
  const std::uint8_t function = pdu[0];
  const std::uint8_t unit = frame[6];
  if (!units.has_unit(unit)) return refuse(frame, function, exception::gateway_target_failed, out);
  switch (function) {
    case read_input:
      return answer_read(frame, pdu, units.input_registers(unit), out);
    case read_holding:
      if (!units.writable()) return refuse(frame, function, exception::illegal_function, out);
      return answer_read(frame, pdu, units.holding_registers(unit), out);
    case write_single:
    case write_multiple:
      if (!units.writable()) return refuse(frame, function, exception::illegal_function, out);
      return answer_write(frame, pdu, units, out);
    default:
      return refuse(frame, function, exception::illegal_function, out);
  }
}

}  // namespace rangekit::modbus
