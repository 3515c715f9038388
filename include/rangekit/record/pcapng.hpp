// Serial-line recordings as pcapng (docs/capture.md): a section header whose comments carry the
// line settings and the family, one interface of link type LINKTYPE_RTAC_SERIAL (250), and one
// packet per chunk read, with who sent it in the packet's flags and in the RTAC header's event
// type. Pure bytes in and out: the file itself is the caller's.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rangekit/core/framer.hpp"
#include "rangekit/core/result.hpp"

namespace rangekit::record {

// Who sent a chunk of a conversation. As pcapng and the RTAC header see it from the host's
// port: what the host sent is outbound (transmitted), what the sensor sent is inbound (received).
enum class Sender : std::uint8_t { host, sensor };
const char* sender_name(Sender sender) noexcept;  // "host", "sensor"

inline constexpr std::uint16_t linktype_rtac_serial = 250;
inline constexpr std::size_t rtac_header_size = 12;

// One chunk of bytes as one sender's port delivered it.
struct SerialChunk {
  Sender sender = Sender::host;
  std::chrono::system_clock::time_point time;  // when it was read (µs kept)
  std::string bytes;
};

// The section header block: each comment an opt_comment ("line 115200 8N1", "family uls"),
// and the program that wrote it (shb_userappl).
std::string pcapng_section_header(const std::vector<std::string>& comments, std::string_view application);
// The interface description block of the serial line: link type 250, microsecond timestamps.
std::string pcapng_serial_interface(std::string_view name);
// An enhanced packet block on interface 0: the RTAC header (time, event type
// DATA_TX_START for the host or DATA_RX_START for the sensor) and the chunk's bytes.
std::string pcapng_serial_packet(const SerialChunk& chunk);

// What a pcapng file holds for a serial conversation, read back.
struct SerialRecording {
  std::vector<std::string> comments;  // the section header's
  std::vector<SerialChunk> chunks;
};

// One block at the front of `buffer`: complete (`consumed` its length), need_more, or invalid
// with the reason (a block length that is not a multiple of 4, its two lengths differ, ...).
FrameScan scan_pcapng_block(Bytes buffer) noexcept;
// A whole file's bytes. Blocks of other types are skipped; an interface of another link type,
// a big-endian section or a damaged block is an error that names it and its offset.
Result<SerialRecording> read_serial_pcapng(std::string_view file);

}  // namespace rangekit::record
