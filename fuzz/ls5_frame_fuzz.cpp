// Both LS5 scan directions through the core FrameAssembler, every frame through
// the request or reply parser, and every parse that succeeds through an
// encode -> parse round trip that must agree.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "rangekit/core/framer.hpp"
#include "rangekit/ls5/reply.hpp"
#include "rangekit/ls5/request.hpp"

using namespace rangekit;
using namespace rangekit::ls5;

namespace {

void check(bool condition) {
  if (!condition) std::abort();
}

void round_trip(const Request& request) {
  const auto encoded = encode_request(request);
  check(encoded.ok());
  const auto again = parse_request_line(encoded->bytes());
  check(again.ok() && *again == request);
}

void round_trip(const Reply& reply) {
  const auto encoded = encode_reply(reply);
  check(encoded.ok());
  const auto again = parse_reply_line(encoded->bytes());
  check(again.ok());
  const auto encoded_again = encode_reply(*again);
  check(encoded_again.ok() && encoded_again->view() == encoded->view());
}

void parse_all(Bytes bytes) {
  if (const auto request = parse_request(bytes); request.ok()) round_trip(*request);
  if (const auto request = parse_request_line(bytes); request.ok()) round_trip(*request);
  if (const auto reply = parse_reply(bytes); reply.ok()) round_trip(*reply);
  if (const auto reply = parse_reply_line(bytes); reply.ok()) round_trip(*reply);
}

// Feeds `bytes` in pieces of 1 to 13 bytes, so frames straddle pushes. `push` gets each
// piece and returns how many bytes it took (the rest comes again), or nothing to stop.
template <class Push>
void in_pieces(Bytes bytes, Push&& push) {
  std::size_t offset = 0;
  std::size_t piece = 1;
  while (offset < bytes.size()) {
    const std::size_t size = piece < bytes.size() - offset ? piece : bytes.size() - offset;
    const std::optional<std::size_t> taken = push(bytes.subspan(offset, size));
    if (!taken) return;
    offset += *taken;
    piece = piece % 13 + 1;
  }
}

void assemble(ScanFunction scan, Bytes bytes, bool requests) {
  FrameAssembler assembler(scan, 128);
  FrameAssembler::Event event;
  in_pieces(bytes, [&](Bytes piece) -> std::optional<std::size_t> {
    const std::size_t taken = assembler.push(piece);
    bool progressed = taken > 0;
    while (assembler.next(event)) {
      progressed = true;
      if (event.kind == FrameAssembler::Event::Kind::rejected) {
        check(event.reason != nullptr && event.rejected_bytes > 0);
        continue;
      }
      check(!event.frame.empty() && event.frame.size() <= max_frame_length);
      if (requests) {
        if (const auto request = parse_request(event.frame); request.ok()) round_trip(*request);
      } else {
        if (const auto reply = parse_reply(event.frame); reply.ok()) round_trip(*reply);
      }
    }
    check(progressed);
    return taken;
  });
}

// The stream reader's decode_replies against next() and parse_reply on every frame, fed
// the same pieces: the same records, replies (or errors) and rejections, in order.
void decode_replies_agrees(Bytes bytes) {
  FrameAssembler by_frame(scan_reply_frame, 128);
  FrameAssembler direct(scan_reply_frame, 128);
  std::vector<std::string> expected;
  std::vector<std::string> got;
  auto describe = [](const Result<Reply>& reply) {
    if (!reply) return "error " + reply.error().message;
    return "reply " + std::to_string(static_cast<int>(reply->kind)) + " " + std::to_string(reply->address) + " " +
           std::to_string(static_cast<int>(reply->command)) + " " + std::to_string(reply->result.value) + " " +
           std::to_string(static_cast<int>(reply->result.kind));
  };
  auto rejected = [](const FrameAssembler::Event& event) {
    return "rejected " + std::to_string(event.rejected_bytes) + " " + (event.reason ? event.reason : "-");
  };
  FrameAssembler::Event event;
  in_pieces(bytes, [&](Bytes piece) -> std::optional<std::size_t> {
    const std::size_t taken = by_frame.push(piece);
    check(direct.push(piece) == taken);
    while (by_frame.next(event)) {
      expected.push_back(event.kind == FrameAssembler::Event::Kind::rejected ? rejected(event)
                                                                             : describe(parse_reply(event.frame)));
    }
    decode_replies(
        direct, [&](ResultCode code) { got.push_back(describe(Reply::stream_record(code))); },
        [&](Bytes, const Result<Reply>& reply) { got.push_back(describe(reply)); },
        [&](const FrameAssembler::Event& rejection) { got.push_back(rejected(rejection)); });
    check(got == expected);
    check(direct.buffered() == by_frame.buffered());
    if (taken == 0 && expected.empty()) return std::nullopt;
    expected.clear();
    got.clear();
    return taken;
  });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const Bytes bytes(data, size);
  parse_all(bytes);
  assemble(scan_request_frame, bytes, true);
  assemble(scan_reply_frame, bytes, false);
  decode_replies_agrees(bytes);
  return 0;
}
