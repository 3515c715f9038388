// Serial recordings as pcapng: block bytes worked out by hand from the pcapng specification
// (draft-ietf-opsawg-pcapng: SHB, IDB, EPB, options padded to 32 bits) and Wireshark's RTAC
// serial header (12 bytes: seconds and microseconds big-endian, event type, control lines,
// footer); read back by our reader and by Debian's tshark.
#include "rangekit/record/pcapng.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <memory>

#include "record/temp_dir.hpp"

namespace {

using namespace rangekit;
using namespace rangekit::record;
using rangekit::record::testing::TempDir;

std::string hex(std::string_view bytes) {
  std::string out;
  std::array<char, 4> digits{};
  for (const char c : bytes) {
    std::snprintf(digits.data(), digits.size(), "%02x", static_cast<unsigned char>(c));
    out += digits.data();
  }
  return out;
}

SerialChunk chunk(Sender sender, std::int64_t micros, std::string bytes) {
  return SerialChunk{sender, std::chrono::system_clock::time_point(std::chrono::microseconds(micros)),
                     std::move(bytes)};
}

TEST(Pcapng, ASectionHeaderWithOneComment) {
  // Type, length 44 (4 + 4 + 4 + 4 + 8 + 4 + 8 + 4 + 4), magic, version 1.0, section length -1,
  // opt_comment (1) of 6 bytes padded to 8, opt_endofopt, length again.
  EXPECT_EQ(hex(pcapng_section_header({"family"}, "")),
            "0a0d0d0a"
            "2c000000"
            "4d3c2b1a"
            "0100"
            "0000"
            "ffffffffffffffff"
            "0100"
            "0600"
            "66616d696c790000"
            "00000000"
            "2c000000");
}

TEST(Pcapng, TheSerialInterfaceIsLinkType250InMicroseconds) {
  // Length 32: type, length, link type 250 and reserved, snaplen 0, if_tsresol (9) = 6 padded
  // to 4, opt_endofopt, length.
  EXPECT_EQ(hex(pcapng_serial_interface("")),
            "01000000"
            "20000000"
            "fa00"
            "0000"
            "00000000"
            "0900"
            "0100"
            "06000000"
            "00000000"
            "20000000");
}

TEST(Pcapng, AHostChunkIsOutboundAndDataTxStart) {
  // "$MM\r" sent by the host at 1.000002 s: timestamp 1000002 µs (0x000F4242), 16 bytes of
  // data (the RTAC header, then the chunk), epb_flags outbound (2), 60 bytes in all.
  EXPECT_EQ(hex(pcapng_serial_packet(chunk(Sender::host, 1000002, "$MM\r"))),
            "06000000"
            "3c000000"
            "00000000"
            "00000000"
            "42420f00"
            "10000000"
            "10000000"
            "00000001"
            "00000002"
            "01"
            "00"
            "0000"
            "244d4d0d"
            "0200"
            "0400"
            "02000000"
            "00000000"
            "3c000000");
  // The sensor's is inbound (1) and DATA_RX_START (2).
  const std::string reply = hex(pcapng_serial_packet(chunk(Sender::sensor, 0, "!")));
  EXPECT_NE(reply.find("000000000000000002"
                       "00"
                       "0000"
                       "21"),
            std::string::npos)
      << reply;
  EXPECT_NE(reply.find("0200"
                       "0400"
                       "01000000"),
            std::string::npos)
      << reply;
}

const std::string section = pcapng_section_header({"family uls", "line 9600 8N1"}, "rangekit test");

std::string recording() {
  std::string file = section;
  file += pcapng_serial_interface("tap");
  file += pcapng_serial_packet(chunk(Sender::host, 1765098000000001, "$MM\r"));
  file += pcapng_serial_packet(chunk(Sender::sensor, 1765098000012345, "$MM,1\r\n"));
  return file;
}

TEST(Pcapng, ReadsBackWhatItWrote) {
  auto read = read_serial_pcapng(recording());
  ASSERT_TRUE(read.ok()) << read.error().message;
  EXPECT_EQ(read->comments, (std::vector<std::string>{"family uls", "line 9600 8N1"}));
  ASSERT_EQ(read->chunks.size(), 2u);
  EXPECT_EQ(read->chunks[0].sender, Sender::host);
  EXPECT_EQ(read->chunks[0].bytes, "$MM\r");
  EXPECT_EQ(read->chunks[1].sender, Sender::sensor);
  EXPECT_EQ(read->chunks[1].bytes, "$MM,1\r\n");
  EXPECT_EQ(std::chrono::duration_cast<std::chrono::microseconds>(read->chunks[1].time.time_since_epoch()).count(),
            1765098000012345);
}

TEST(Pcapng, ADamagedFileIsRefusedWithWhereAndWhy) {
  const std::string file = recording();
  const auto refused = [](std::string_view bytes, const std::string& why) {
    auto read = read_serial_pcapng(bytes);
    ASSERT_FALSE(read.ok()) << why;
    EXPECT_NE(read.error().message.find(why), std::string::npos) << read.error().message;
  };
  refused(file.substr(0, file.size() - 3), "the file ends inside it");
  refused(file.substr(section.size()), "no section header first");
  std::string lengths = file;
  lengths[4] = 0x2C;  // the section header's first length no longer matches its last
  refused(lengths, "block at byte 0: its two lengths differ");
  std::string odd = file;
  odd[4] = 0x29;
  refused(odd, "not a multiple of 4");
  std::string ethernet = file;
  ethernet[section.size() + 8] = 1;  // the interface's link type: Ethernet
  refused(ethernet, "block at byte " + std::to_string(section.size()) + ": link type 1, not RTAC serial (250)");
  std::string future = file;
  const std::size_t packet = section.size() + pcapng_serial_interface("tap").size();
  future[packet + 12 + 3] = static_cast<char>(0xFF);  // the timestamp's high word: 0xFF000000 << 32 µs
  refused(future, "block at byte " + std::to_string(packet) + ": a timestamp past the year 2262");
  refused("", "empty file");
}

// What a command prints, stderr with it.
std::string output_of(const std::string& command) {
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(::popen((command + " 2>&1").c_str(), "r"), ::pclose);
  std::string out;
  if (!pipe) return out;
  std::array<char, 256> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe.get()) != nullptr) out += buffer.data();
  return out;
}

TEST(Pcapng, TsharkReadsTheDirectionTheBytesAndTheComments) {
  TempDir dir;
  const std::string path = dir.file("session.pcapng");
  std::ofstream(path, std::ios::binary) << recording();
  const std::string out =
      output_of("tshark -r " + path + " -T fields -e frame.packet_flags_direction -e rtacser.eventtype -e data.data");
  // Outbound (2) and DATA_TX_START (1) for the host; inbound (1) and DATA_RX_START (2) for the sensor.
  EXPECT_NE(out.find("0x00000002\t0x01\t244d4d0d\n"), std::string::npos) << out;
  EXPECT_NE(out.find("0x00000001\t0x02\t244d4d2c310d0a\n"), std::string::npos) << out;
  const std::string info = output_of("capinfos -k " + path);
  EXPECT_NE(info.find("family uls"), std::string::npos) << info;
  EXPECT_NE(info.find("line 9600 8N1"), std::string::npos) << info;
}

}  // namespace
