// The LS5 decoders against their recorded outputs on a large corpus, malformed lines
// included, so optimising them leaves every output unchanged (tests/decoder_corpus.hpp).
// Serial replies (§9.2, L1) and UDP datagrams (§10.1, L12), each also damaged, are digested.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "decoder_corpus.hpp"
#include "rangekit/ls5/ls5.hpp"

namespace rangekit::ls5 {
namespace {

using testing::corpus::Digest;
using testing::corpus::escaped;
using testing::corpus::exact;
using testing::corpus::Random;

constexpr std::size_t corpus_lines = 60000;
constexpr std::size_t corpus_datagrams = 6000;

std::uint16_t random_code(Random& random) {
  switch (random.below(20)) {
    case 0:
      return code_no_signal;
    case 1:
      return code_no_measurement_yet;
    case 2:
      return static_cast<std::uint16_t>(random.below(65536));
    default:
      return static_cast<std::uint16_t>(random.below(max_result_code + 1));
  }
}

std::uint8_t random_address(Random& random) {
  return random.one_in(10) ? static_cast<std::uint8_t>(random.below(256)) : std::uint8_t{1};
}

// One reply as the emulator writes it, or an identification, or junk.
std::string random_line(Random& random) {
  Reply reply = Reply::stream_record(ResultCode{});
  switch (random.below(16)) {
    case 0:
      reply =
          Reply::result_of(random_address(random), random.one_in(2) ? CommandId::read_latched : CommandId::read_last,
                           ResultCode{random_code(random), CodeKind::result});
      break;
    case 1:
      reply = Reply::parameter_value(random_address(random), static_cast<std::uint8_t>(random.below(256)),
                                     static_cast<std::uint8_t>(random.below(256)));
      break;
    case 2: {
      Request request;
      request.address = random_address(random);
      request.command = static_cast<CommandId>(random.below(command_count));
      request.parameter = static_cast<std::uint8_t>(random.below(256));
      request.value = static_cast<std::uint8_t>(random.below(256));
      reply = Reply::echo(request);
      break;
    }
    case 3: {
      if (random.one_in(2)) return "%01LS5.6.0   b8,1234d40,0010s/n0000157\r";
      auto id = make_identification("LS5.6.0", random.below(100000) / 1000.0, random.below(1000000) / 1000.0,
                                    random.below(10000000));
      if (!id) return "%01\r";
      reply = Reply::identification_of(random_address(random), *id);
      break;
    }
    case 4:
      return random.one_in(2) ? "!1234567\r" : "\r\n";
    default: {
      const std::uint16_t code = random_code(random);
      reply = Reply::stream_record(ResultCode{code, CodeKind::result});
      break;
    }
  }
  auto text = encode_reply(reply);
  if (!text) return "!" + std::to_string(reply.result.value) + "\r";  // a code the encoder refuses
  return std::string(text->view());
}

std::string describe(const Error& error) { return std::string(errc_name(error.code)) + " " + error.message; }

std::string describe(const Reply& reply) {
  std::string text = "kind " + std::to_string(static_cast<int>(reply.kind)) + " addr " + std::to_string(reply.address) +
                     " cmd " + std::to_string(static_cast<int>(reply.command)) + " p " +
                     std::to_string(reply.parameter) + " v " + std::to_string(reply.value) + " code " +
                     std::to_string(reply.result.value) + "/" + std::to_string(static_cast<int>(reply.result.kind));
  if (reply.kind == ReplyKind::identification) {
    const Identification& id = reply.identification;
    text += " id <" + std::string(id.version_text.view()) + "> " + (id.version ? "v" : "-") + " " +
            exact(id.lower_boundary_mm) + " " + exact(id.range_mm) + " " + std::to_string(id.serial_number);
  }
  return text;
}

// L1, L2, L7 and table 9.1's reply forms, all at once: the whole output for the corpus.
TEST(Ls5DecoderCorpus, SerialRepliesMatchTheRecordedOutputs) {
  Random random(17);
  const std::string stream = testing::corpus::corpus_stream(random, corpus_lines, random_line);

  Digest framing("ls5_framing");
  Digest parsing("ls5_parse_reply");
  testing::corpus::frame_in_chunks(stream, &scan_reply_frame, random, framing, [&](Bytes frame) {
    const Result<Reply> reply = parse_reply(frame);
    parsing.add(reply ? describe(*reply) : describe(reply.error()));
  });

  // The replies and error codes of the unoptimised decoders of commit 3310b0b, in the
  // messages' present words (the digests hash both).
  EXPECT_EQ(framing.lines(), 60221U);
  EXPECT_EQ(framing.hex(), "0ddba90e7d7ba62e");
  EXPECT_EQ(parsing.lines(), 53510U);
  EXPECT_EQ(parsing.hex(), "7327f6ff63cdfe0a");
}

// The stream reader's path: decode_replies reads good "!ddddd" records straight
// from the framer's buffer and everything else through next() and parse_reply. It must
// give the same frames, rejections and replies, in the same order, as the test above:
// the same recorded digests (L1: "!ddddd<CR>", L7: codes 0-50000, 65534, 65535).
TEST(Ls5DecoderCorpus, DecodeRepliesMatchesTheRecordedOutputs) {
  Random random(17);
  const std::string stream = testing::corpus::corpus_stream(random, corpus_lines, random_line);

  Digest framing("ls5_framing_decode_replies");
  Digest parsing("ls5_parse_reply_decode_replies");
  std::size_t records = 0;
  auto on_record = [&](ResultCode code) {
    // The frame it came from: '!' and the code in five digits, as on the wire (L1).
    std::string frame = std::to_string(code.value);
    frame = "!" + std::string(5 - frame.size(), '0') + frame;
    testing::corpus::add_frame(framing, as_bytes(frame));
    parsing.add(describe(Reply::stream_record(code)));
    ++records;
  };
  auto on_reply = [&](Bytes frame, const Result<Reply>& reply) {
    testing::corpus::add_frame(framing, frame);
    parsing.add(reply ? describe(*reply) : describe(reply.error()));
  };
  auto on_rejected = [&](const FrameAssembler::Event& event) { testing::corpus::add_rejection(framing, event); };
  testing::corpus::feed_in_chunks(stream, &scan_reply_frame, random, [&](FrameAssembler& assembler) {
    decode_replies(assembler, on_record, on_reply, on_rejected);
  });

  EXPECT_GT(records, 30000U);  // most records took the direct path
  // The digests recorded with the unoptimised decoders of commit 3310b0b, as above.
  EXPECT_EQ(framing.lines(), 60221U);
  EXPECT_EQ(framing.hex(), "0ddba90e7d7ba62e");
  EXPECT_EQ(parsing.lines(), 53510U);
  EXPECT_EQ(parsing.hex(), "7327f6ff63cdfe0a");
}

// §10.1: "the checksum is the XOR of bytes 0-509"; state bit 1 always 1, bits 4-7 always 0 (L12),
// a record with another word kept in its decoded packet (L85).
TEST(Ls5DecoderCorpus, UdpDatagramsMatchTheRecordedOutputs) {
  Random random(1017);
  Digest decoding("ls5_udp");
  for (std::size_t n = 0; n < corpus_datagrams; ++n) {
    UdpPacket packet;
    for (auto& record : packet.records) {
      record.code = static_cast<std::uint16_t>(random.below(0x4400));
      record.state = static_cast<std::uint8_t>(udp_state::always_one | random.below(16));
    }
    packet.serial_number = static_cast<std::uint16_t>(random.below(65536));
    packet.lower_boundary_mm = static_cast<std::uint16_t>(random.below(65536));
    packet.range_mm = static_cast<std::uint16_t>(random.below(65536));
    packet.counter = static_cast<std::uint8_t>(random.below(256));
    std::array<std::uint8_t, udp_packet_size> bytes{};
    ASSERT_TRUE(encode_udp_packet(packet, bytes).ok());
    std::vector<std::uint8_t> datagram(bytes.begin(), bytes.end());
    switch (random.below(6)) {
      case 0:
        break;
      case 1:  // a flipped byte anywhere
        datagram[random.below(udp_packet_size)] ^= static_cast<std::uint8_t>(1 + random.below(255));
        break;
      case 2: {  // a bad state byte with a repaired checksum: decoded, the record left to the caller (L85)
        const std::size_t record = random.below(udp_record_count);
        datagram[record * 3 + 2] = static_cast<std::uint8_t>(random.below(256));
        std::uint8_t sum = 0;
        for (std::size_t i = 0; i < udp_offset::counter; ++i) sum ^= datagram[i];
        datagram[udp_offset::checksum] = sum;
        break;
      }
      case 3:  // cut short or lengthened
        datagram.resize(random.one_in(2) ? random.below(udp_packet_size) : udp_packet_size + 1 + random.below(64));
        break;
      case 4:  // the counter and checksum bytes are outside the XOR
        datagram[udp_offset::counter] ^= 0x55;
        break;
      default:
        datagram[udp_offset::checksum] ^= static_cast<std::uint8_t>(1U << random.below(8));
        break;
    }
    const Result<UdpPacket> decoded = decode_udp_packet(datagram);
    if (!decoded) {
      decoding.add(describe(decoded.error()));
      continue;
    }
    std::string text = "ok " + std::to_string(decoded->serial_number) + " " +
                       std::to_string(decoded->lower_boundary_mm) + " " + std::to_string(decoded->range_mm) + " " +
                       std::to_string(decoded->counter);
    for (const auto& record : decoded->records) {
      text += " " + std::to_string(record.code) + ":" + std::to_string(record.state);
    }
    decoding.add(text);
  }
  // The replies and error codes of the unoptimised decoders of commit 3310b0b, in the
  // messages' present words (the digests hash both); a packet whose only fault is a state
  // word decodes, an "ok" line with the word as sent (L85).
  EXPECT_EQ(decoding.lines(), 6000U);
  EXPECT_EQ(decoding.hex(), "b136d52b618b2078");
}

}  // namespace
}  // namespace rangekit::ls5
