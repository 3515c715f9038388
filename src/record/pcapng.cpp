// Block layouts from the pcapng specification (draft-ietf-opsawg-pcapng): SHB 0x0A0D0D0A,
// IDB 1, EPB 6, options padded to 32 bits; written little-endian, as the machines we run on.
#include "rangekit/record/pcapng.hpp"

#include <cstring>

namespace rangekit::record {
namespace {

constexpr std::uint32_t section_header_type = 0x0A0D0D0A;
constexpr std::uint32_t interface_type = 1;
constexpr std::uint32_t enhanced_packet_type = 6;
constexpr std::uint32_t byte_order_magic = 0x1A2B3C4D;
constexpr std::uint16_t opt_comment = 1;
constexpr std::uint16_t shb_userappl = 4;
constexpr std::uint16_t if_name = 2;
constexpr std::uint16_t if_tsresol = 9;
constexpr std::uint16_t epb_flags = 2;
constexpr std::uint32_t inbound = 1;  // epb_flags bits 0-1
constexpr std::uint32_t outbound = 2;
constexpr std::uint8_t data_tx_start = 1;  // the RTAC header's event types
constexpr std::uint8_t data_rx_start = 2;
constexpr std::size_t max_block = std::size_t{16} << 20;  // no chunk of a serial line comes near

void put16(std::string& out, std::uint16_t value) {
  out += static_cast<char>(value & 0xFF);
  out += static_cast<char>(value >> 8);
}
void put32(std::string& out, std::uint32_t value) {
  for (int shift = 0; shift < 32; shift += 8) out += static_cast<char>((value >> shift) & 0xFF);
}
void put32_big(std::string& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8) out += static_cast<char>((value >> shift) & 0xFF);
}
void pad(std::string& out) {
  while (out.size() % 4 != 0) out += '\0';
}
void put_option(std::string& out, std::uint16_t code, std::string_view value) {
  put16(out, code);
  put16(out, static_cast<std::uint16_t>(value.size()));
  out += value;
  pad(out);
}
// Type, total length, body, total length again.
std::string block(std::uint32_t type, std::string_view body) {
  std::string out;
  const auto length = static_cast<std::uint32_t>(12 + body.size());
  put32(out, type);
  put32(out, length);
  out += body;
  put32(out, length);
  return out;
}
std::string end_of_options() { return std::string(4, '\0'); }

std::uint32_t get32(std::string_view bytes, std::size_t at) {
  std::uint32_t value = 0;
  for (int i = 3; i >= 0; --i)
    value = (value << 8) | static_cast<unsigned char>(bytes[at + static_cast<std::size_t>(i)]);
  return value;
}
std::uint16_t get16(std::string_view bytes, std::size_t at) {
  return static_cast<std::uint16_t>(static_cast<unsigned char>(bytes[at]) |
                                    (static_cast<unsigned char>(bytes[at + 1]) << 8));
}

// The options from `at` to the block's end: calls `take(code, value)` for each until
// opt_endofopt; false when one runs past the end.
template <class Take>
bool read_options(std::string_view body, std::size_t at, Take take) {
  while (at + 4 <= body.size()) {
    const std::uint16_t code = get16(body, at);
    const std::uint16_t length = get16(body, at + 2);
    if (code == 0) return true;
    if (at + 4 + length > body.size()) return false;
    take(code, body.substr(at + 4, length));
    at += 4 + ((length + 3U) & ~3U);
  }
  return true;
}

Error damaged(std::size_t offset, const std::string& why) {
  return make_error(Errc::invalid_frame, "pcapng: block at byte " + std::to_string(offset) + ": " + why);
}

}  // namespace

const char* sender_name(Sender sender) noexcept { return sender == Sender::host ? "host" : "sensor"; }

std::string pcapng_section_header(const std::vector<std::string>& comments, std::string_view application) {
  std::string body;
  put32(body, byte_order_magic);
  put16(body, 1);           // major
  put16(body, 0);           // minor
  put32(body, 0xFFFFFFFF);  // section length: not given (-1)
  put32(body, 0xFFFFFFFF);
  for (const std::string& comment : comments) put_option(body, opt_comment, comment);
  if (!application.empty()) put_option(body, shb_userappl, application);
  body += end_of_options();
  return block(section_header_type, body);
}

std::string pcapng_serial_interface(std::string_view name) {
  std::string body;
  put16(body, linktype_rtac_serial);
  put16(body, 0);  // reserved
  put32(body, 0);  // snaplen: no limit
  if (!name.empty()) put_option(body, if_name, name);
  put_option(body, if_tsresol, std::string_view("\x06", 1));  // microseconds
  body += end_of_options();
  return block(interface_type, body);
}

std::string pcapng_serial_packet(const SerialChunk& chunk) {
  const auto micros = std::chrono::duration_cast<std::chrono::microseconds>(chunk.time.time_since_epoch()).count();
  const auto stamp = static_cast<std::uint64_t>(micros);
  std::string data;
  put32_big(data, static_cast<std::uint32_t>(stamp / 1000000));
  put32_big(data, static_cast<std::uint32_t>(stamp % 1000000));
  data += static_cast<char>(chunk.sender == Sender::host ? data_tx_start : data_rx_start);
  data += '\0';                  // control lines: none known
  data += std::string(2, '\0');  // footer
  data += chunk.bytes;
  std::string body;
  put32(body, 0);  // interface 0
  put32(body, static_cast<std::uint32_t>(stamp >> 32));
  put32(body, static_cast<std::uint32_t>(stamp & 0xFFFFFFFF));
  put32(body, static_cast<std::uint32_t>(data.size()));
  put32(body, static_cast<std::uint32_t>(data.size()));
  body += data;
  pad(body);
  std::string flags;
  put32(flags, chunk.sender == Sender::host ? outbound : inbound);
  put_option(body, epb_flags, flags);
  body += end_of_options();
  return block(enhanced_packet_type, body);
}

FrameScan scan_pcapng_block(Bytes buffer) noexcept {
  if (buffer.size() < 12) return FrameScan::need_more();
  const std::string_view bytes = as_text(buffer);
  const std::uint32_t length = get32(bytes, 4);
  if (length < 12 || length % 4 != 0)
    return FrameScan::invalid(buffer.size(), "block length is not a multiple of 4 of at least 12");
  if (length > max_block) return FrameScan::invalid(buffer.size(), "block longer than 16 MiB");
  if (buffer.size() < length) return FrameScan::need_more();
  if (get32(bytes, length - 4) != length) return FrameScan::invalid(buffer.size(), "its two lengths differ");
  return FrameScan::complete(buffer.first(length), length);
}

Result<SerialRecording> read_serial_pcapng(std::string_view file) {
  SerialRecording recording;
  bool section = false;
  bool serial_interface = false;
  std::size_t offset = 0;
  while (offset < file.size()) {
    const FrameScan scan = scan_pcapng_block(as_bytes(file.substr(offset)));
    if (scan.status == FrameStatus::need_more) return damaged(offset, "the file ends inside it");
    if (scan.status == FrameStatus::invalid) return damaged(offset, scan.reason);
    const std::string_view whole = as_text(scan.frame);
    const std::uint32_t type = get32(whole, 0);
    const std::string_view body = whole.substr(8, whole.size() - 12);
    if (type == section_header_type) {
      if (body.size() < 16 || get32(body, 0) != byte_order_magic) {
        return damaged(offset, "a section that is not little-endian pcapng (byte-order magic)");
      }
      section = true;
      if (!read_options(body, 16, [&](std::uint16_t code, std::string_view value) {
            if (code == opt_comment) recording.comments.emplace_back(value);
          })) {
        return damaged(offset, "an option runs past the block");
      }
    } else if (!section) {
      return damaged(offset, "no section header first: not a pcapng file");
    } else if (type == interface_type) {
      if (body.size() < 8) return damaged(offset, "interface block too short");
      if (serial_interface) return damaged(offset, "a second interface: a serial recording has one");
      if (get16(body, 0) != linktype_rtac_serial) {
        return damaged(offset, "link type " + std::to_string(get16(body, 0)) + ", not RTAC serial (250)");
      }
      serial_interface = true;
    } else if (type == enhanced_packet_type) {
      if (!serial_interface) return damaged(offset, "a packet before its interface");
      if (body.size() < 20) return damaged(offset, "packet block too short");
      const std::uint32_t captured = get32(body, 12);
      if (20 + static_cast<std::size_t>(captured) > body.size()) return damaged(offset, "packet data past the block");
      if (captured < rtac_header_size) return damaged(offset, "packet shorter than its RTAC header");
      const std::string_view data = body.substr(20, captured);
      SerialChunk chunk;
      const std::uint64_t stamp = (static_cast<std::uint64_t>(get32(body, 4)) << 32) | get32(body, 8);
      // The clock counts in ns from 1970 in 64 bits: µs past 2262 cannot be held.
      constexpr auto latest = static_cast<std::uint64_t>(
          std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::duration::max()).count());
      if (stamp > latest) return damaged(offset, "a timestamp past the year 2262");
      chunk.time = std::chrono::system_clock::time_point(std::chrono::microseconds(stamp));
      const auto event = static_cast<std::uint8_t>(data[8]);
      if (event != data_tx_start && event != data_rx_start) {
        return damaged(offset, "RTAC event type " + std::to_string(event) + " is not DATA_TX_START or DATA_RX_START");
      }
      chunk.sender = event == data_tx_start ? Sender::host : Sender::sensor;
      chunk.bytes.assign(data.substr(rtac_header_size));
      recording.chunks.push_back(std::move(chunk));
    }
    offset += scan.consumed;
  }
  if (!section) return make_error(Errc::invalid_frame, "pcapng: empty file");
  return recording;
}

}  // namespace rangekit::record
