// Malformed input: every bad frame or packet gives an Error value whose message
// names the problem; nothing throws or crashes. Then 100k random buffers
// (fixed seed) through the framers and every parser, and random UDP datagrams.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <string>
#include <vector>

#include "rangekit/ls5/frame.hpp"
#include "rangekit/ls5/identification.hpp"
#include "rangekit/ls5/reply.hpp"
#include "rangekit/ls5/request.hpp"
#include "rangekit/ls5/udp_packet.hpp"
#include "test_helpers.hpp"

using namespace rangekit;
using namespace rangekit::ls5;
using ls5_test::bytes_of;

namespace {

struct BadLine {
  std::string text;
  Errc code;
  std::string_view says;  // part of the message
};

void expect_rejected(const Result<Request>& result, const BadLine& line) {
  ASSERT_FALSE(result.ok()) << line.text;
  EXPECT_EQ(result.error().code, line.code) << line.text << ": " << result.error().describe();
  EXPECT_NE(result.error().message.find(line.says), std::string::npos)
      << line.text << ": '" << result.error().message << "' should say '" << line.says << "'";
}

void expect_rejected(const Result<Reply>& result, const BadLine& line) {
  ASSERT_FALSE(result.ok()) << line.text;
  EXPECT_EQ(result.error().code, line.code) << line.text << ": " << result.error().describe();
  EXPECT_NE(result.error().message.find(line.says), std::string::npos)
      << line.text << ": '" << result.error().message << "' should say '" << line.says << "'";
}

const std::string id_field = "LS5.6.0   b8,1234d40,0010s/n0000157";  // §9.2, L2

}  // namespace

TEST(Ls5Malformed, Requests) {
  const BadLine lines[] = {
      {"#0\r", Errc::truncated, "two-digit network address"},
      {"#01\r", Errc::truncated, "ends before its command"},
      {"#01O\r", Errc::truncated, "cut short"},
      {"#01W0B0\r", Errc::truncated, "W takes a parameter address and a value"},
      {"#01R\r", Errc::truncated, "R takes a parameter address"},
      {"#01ONX\r", Errc::overlong, "unexpected 'X' after ON"},
      {"#01W0B011\r", Errc::overlong, "unexpected '1' after W"},
      {"#01R0G\r", Errc::bad_hex, "parameter address '0G' is not hex"},
      {"#01W0BZZ\r", Errc::bad_hex, "parameter value 'ZZ' is not hex"},
      {"#G1ON\r", Errc::bad_hex, "network address 'G1' is not hex"},
      {"#01XY\r", Errc::unknown_command, "'XY' in '#01XY' is not an LS5 command"},
      {"#00ID\r", Errc::wrong_form, "broadcast"},
      // Wrong terminator, missing terminator, bytes after it.
      {"#01ON\n", Errc::invalid_frame, "line feed inside a frame"},
      {"#01ON", Errc::truncated, "does not end with CR"},
      {"#01ON\r#", Errc::overlong, "bytes after the CR"},
      {"#01ON\r\r", Errc::overlong, "bytes after the CR"},
      // Embedded NUL and other control bytes.
      {std::string("#01O\0N\r", 7), Errc::invalid_frame, "control or non-ASCII byte"},
      {"#01\x7fON\r", Errc::invalid_frame, "control or non-ASCII byte"},
      // Overlong frame (F5), a reply on the request side, bytes before '#'.
      {"#01" + std::string(70, 'A') + "\r", Errc::invalid_frame, "longer than the protocol allows"},
      {"!01ON\r", Errc::invalid_frame, "bytes before the start of a frame"},
      {"x#01ON\r", Errc::invalid_frame, "bytes before the start of a frame"},
      {"#01#01ON\r", Errc::invalid_frame, "cut short by a new start byte"},
      {"", Errc::truncated, "does not end with CR"},
  };
  for (const BadLine& line : lines) expect_rejected(parse_request_line(bytes_of(line.text)), line);

  // The parser itself, given bytes that did not come through the framer.
  expect_rejected(parse_request(bytes_of(std::string("#01O\0N", 6))),
                  {"#01O\\0N", Errc::invalid_frame, "byte 0x00 at position 4"});
  expect_rejected(parse_request(bytes_of("#01ON\r")), {"#01ON\\r", Errc::invalid_frame, "byte 0x0D at position 5"});
  expect_rejected(parse_request(bytes_of("")), {"(empty)", Errc::truncated, "empty request"});
  expect_rejected(parse_request(bytes_of("!01ON")), {"!01ON", Errc::invalid_frame, "a request starts with '#'"});
}

TEST(Ls5Malformed, Replies) {
  const BadLine lines[] = {
      {"!50001\r", Errc::out_of_range, "50001 is invalid"},
      {"!65533\r", Errc::out_of_range, "65533 is invalid"},
      {"!2500\r", Errc::truncated, "5 digits"},
      {"!01FR2500\r", Errc::truncated, "FR takes a 5-digit result"},
      {"!01FR250000\r", Errc::overlong, "unexpected '0' after FR"},
      {"!01FR25A00\r", Errc::bad_number, "result '25A00'"},
      {"!01LR50001\r", Errc::out_of_range, "50001 is invalid"},
      {"!01R05\r", Errc::truncated, "R takes a parameter address and value"},
      {"!01R05G5\r", Errc::bad_hex, "parameter value 'G5' is not hex"},
      {"!01ID\r", Errc::wrong_form, "starts with '%'"},
      {"!01ST\r", Errc::wrong_form, "ST has no reply"},
      {"!00ON\r", Errc::wrong_form, "never comes from address 00"},
      {"!01ZZ\r", Errc::unknown_command, "not an LS5 command"},
      {"!0\r", Errc::truncated, "5 digits"},  // digits only: a stream record (L1)
      {"!A\r", Errc::truncated, "network address"},
      {"!\r", Errc::truncated, "ends before"},
      {"!01ON\n", Errc::invalid_frame, "line feed"},
      {std::string("!01\0ON\r", 7), Errc::invalid_frame, "control or non-ASCII byte"},
      // Identification: wrong length, bad fields, address 00.
      {"%01" + id_field.substr(0, 34) + "\r", Errc::truncated, "expected '%', the address and 35 characters"},
      {"%01" + id_field + "0\r", Errc::overlong, "expected '%', the address and 35 characters"},
      {"%01" + id_field.substr(0, 28) + "00001x7\r", Errc::bad_number, "serial number '00001x7'"},
      {"%01" + id_field.substr(0, 11) + "8,12,4" + id_field.substr(17) + "\r", Errc::bad_number, "lower boundary"},
      {"%01" + id_field.substr(0, 18) + "       " + id_field.substr(25) + "\r", Errc::bad_number, "range"},
      {"%01" + id_field.substr(0, 18) + "0000000" + id_field.substr(25) + "\r", Errc::out_of_range, "range is 0"},
      {"%01          " + id_field.substr(10) + "\r", Errc::invalid_frame, "version field is blank"},
      {"%00" + id_field + "\r", Errc::wrong_form, "address 00"},
      {"%G0" + id_field + "\r", Errc::bad_hex, "network address 'G0'"},
      {"#01ON\r", Errc::invalid_frame, "bytes before the start of a frame"},
  };
  for (const BadLine& line : lines) expect_rejected(parse_reply_line(bytes_of(line.text)), line);
  expect_rejected(parse_reply(bytes_of("#01ON")), {"#01ON", Errc::invalid_frame, "a reply starts with '!' or '%'"});
}

TEST(Ls5Malformed, UdpPackets) {
  std::vector<std::uint8_t> zeros(512, 0x00);  // state words 0: bit 1 clear; checksum 0 matches
  const auto no_bit_1 = decode_udp_packet(zeros);
  ASSERT_TRUE(no_bit_1.ok()) << no_bit_1.error().message;  // the records are the caller's to flag (L85)
  EXPECT_EQ(check_udp_state(no_bit_1->records[0].state).error().code, Errc::invalid_frame);
  zeros[0] = 0x01;  // now the XOR of 0-509 is 01, the checksum byte says 00
  const auto checksum = decode_udp_packet(zeros);
  ASSERT_FALSE(checksum.ok());
  EXPECT_EQ(checksum.error().code, Errc::bad_checksum);
  EXPECT_EQ(checksum.error().message, "LS5 UDP packet: checksum byte 0x00, the XOR of bytes 0-509 is 0x01");
  EXPECT_EQ(decode_udp_packet(Bytes(zeros.data(), 100)).error().code, Errc::truncated);
}

namespace {

// Bytes that make frames likely, so random buffers reach deep into the parsers.
constexpr std::string_view alphabet = "#!%0123456789ABCDEFabcdefRWIDFLONSTBXls/, \r";

std::vector<std::uint8_t> random_buffer(std::mt19937& random) {
  std::vector<std::uint8_t> buffer(random() % 80);
  const bool mostly_alphabet = random() % 4 != 0;
  for (auto& byte : buffer) {
    const auto r = random();
    byte = (mostly_alphabet && r % 8 != 0) ? static_cast<std::uint8_t>(alphabet[(r >> 3) % alphabet.size()])
                                           : static_cast<std::uint8_t>(r >> 8);
  }
  // Sometimes a real frame with one byte changed.
  if (random() % 8 == 0) {
    static const std::string seeds[] = {"#01ON\r",  "#02W0B01\r", "!01FR25000\r", "!25000\r", "%01" + id_field + "\r",
                                        "#01R05\r", "!01R0505\r", "!01LR65535\r"};
    const std::string& seed = seeds[random() % std::size(seeds)];
    buffer.assign(seed.begin(), seed.end());
    buffer[random() % buffer.size()] = static_cast<std::uint8_t>(random());
  }
  return buffer;
}

bool names_the_problem(const Error& error) { return !error.message.empty() && error.message.rfind("LS5 ", 0) == 0; }

// A frame that parses re-encodes to text that parses to the same text again.
void check_request_round_trip(const Request& request, int& round_trips) {
  const auto encoded = encode_request(request);
  ASSERT_TRUE(encoded.ok()) << encoded.error().describe();
  const auto again = parse_request_line(encoded->bytes());
  ASSERT_TRUE(again.ok()) << again.error().describe();
  EXPECT_EQ(*again, request);
  ++round_trips;
}

void check_reply_round_trip(const Reply& reply, int& round_trips) {
  const auto encoded = encode_reply(reply);
  ASSERT_TRUE(encoded.ok()) << encoded.error().describe();
  const auto again = parse_reply_line(encoded->bytes());
  ASSERT_TRUE(again.ok()) << again.error().describe();
  const auto encoded_again = encode_reply(*again);
  ASSERT_TRUE(encoded_again.ok());
  EXPECT_EQ(encoded_again->view(), encoded->view());
  ++round_trips;
}

}  // namespace

TEST(Ls5Malformed, RandomBuffersThroughFramersAndParsers) {
  std::mt19937 random(20210601);
  FrameAssembler requests(scan_request_frame, 256);
  FrameAssembler replies(scan_reply_frame, 256);
  int frames = 0;
  int rejected = 0;
  int round_trips = 0;
  for (int i = 0; i < 100000; ++i) {
    const std::vector<std::uint8_t> buffer = random_buffer(random);
    const Bytes bytes(buffer.data(), buffer.size());

    // Whole-buffer parsers.
    for (const auto& result : {parse_request_line(bytes), parse_request(bytes)}) {
      if (result.ok()) {
        check_request_round_trip(*result, round_trips);
      } else {
        ASSERT_TRUE(names_the_problem(result.error())) << result.error().message;
      }
    }
    for (const auto& result : {parse_reply_line(bytes), parse_reply(bytes)}) {
      if (result.ok()) {
        check_reply_round_trip(*result, round_trips);
      } else {
        ASSERT_TRUE(names_the_problem(result.error())) << result.error().message;
      }
    }
    if (buffer.size() >= identification_field_length) {
      const auto id = decode_identification_field(as_text(bytes.first(identification_field_length)));
      if (!id.ok()) {
        ASSERT_TRUE(names_the_problem(id.error())) << id.error().message;
      }
    }

    // Streamed through the assemblers, in two pieces.
    const std::size_t cut = buffer.empty() ? 0 : random() % buffer.size();
    for (FrameAssembler* assembler : {&requests, &replies}) {
      const bool request_side = assembler == &requests;
      for (const Bytes piece : {bytes.first(cut), bytes.subspan(cut)}) {
        assembler->push(piece);
        FrameAssembler::Event event;
        while (assembler->next(event)) {
          if (event.kind == FrameAssembler::Event::Kind::rejected) {
            ASSERT_NE(event.reason, nullptr);
            ++rejected;
            continue;
          }
          ++frames;
          if (request_side) {
            const auto request = parse_request(event.frame);
            if (request.ok()) {
              check_request_round_trip(*request, round_trips);
            } else {
              ASSERT_TRUE(names_the_problem(request.error())) << request.error().message;
            }
          } else {
            const auto reply = parse_reply(event.frame);
            if (reply.ok()) {
              check_reply_round_trip(*reply, round_trips);
            } else {
              ASSERT_TRUE(names_the_problem(reply.error())) << reply.error().message;
            }
          }
        }
      }
    }
  }
  // The corpus reached the parsers, not just the framer.
  EXPECT_GT(frames, 10000);
  EXPECT_GT(rejected, 10000);
  EXPECT_GT(round_trips, 1000);
}

TEST(Ls5Malformed, RandomUdpDatagrams) {
  std::mt19937 random(10);
  std::array<std::uint8_t, 512> datagram{};
  int decoded = 0;
  for (int i = 0; i < 20000; ++i) {
    for (auto& byte : datagram) byte = static_cast<std::uint8_t>(random());
    if (i % 2 == 0) {
      // Give half of them legal state words and a right checksum, so the other
      // checks and the round trip are exercised too.
      for (std::size_t record = 0; record < 168; ++record) {
        auto& state = datagram[record * 3 + 2];
        state = static_cast<std::uint8_t>((state & 0x0D) | 0x02);
        if (random() % 200 == 0) state = static_cast<std::uint8_t>(random());
      }
      datagram[511] = udp_checksum(datagram);
    }
    const std::size_t size = (i % 97 == 0) ? random() % 600 : 512;
    const auto packet = decode_udp_packet(Bytes(datagram.data(), std::min<std::size_t>(size, 512)));
    if (!packet.ok()) {
      ASSERT_TRUE(names_the_problem(packet.error())) << packet.error().message;
      continue;
    }
    ++decoded;
    std::array<std::uint8_t, 512> again{};
    const bool states_valid = std::all_of(packet->records.begin(), packet->records.end(),
                                          [](const UdpRecord& record) { return check_udp_state(record.state).ok(); });
    const Status encoded = encode_udp_packet(*packet, again);
    if (!states_valid) {  // decoded and kept (L85), but the encoder writes only valid words
      ASSERT_FALSE(encoded.ok());
      ASSERT_TRUE(names_the_problem(encoded.error())) << encoded.error().message;
      continue;
    }
    ASSERT_TRUE(encoded.ok());
    EXPECT_EQ(again, datagram);
    for (const UdpRecord& record : packet->records) {
      const auto distance = udp_distance_mm(record, packet->range_mm);
      if (!distance.ok()) {
        ASSERT_TRUE(names_the_problem(distance.error()));
      }
    }
  }
  EXPECT_GT(decoded, 1000);
}
