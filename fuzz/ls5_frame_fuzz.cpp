// Both LS5 scan directions through the core FrameAssembler, every frame through
// the request or reply parser, and every parse that succeeds through an
// encode -> parse round trip that must agree.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

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

void assemble(ScanFunction scan, Bytes bytes, bool requests) {
  FrameAssembler assembler(scan, 128);
  // Push in pieces of varying size, so frames straddle pushes.
  std::size_t offset = 0;
  std::size_t piece = 1;
  FrameAssembler::Event event;
  while (offset < bytes.size()) {
    const std::size_t size = piece < bytes.size() - offset ? piece : bytes.size() - offset;
    const std::size_t taken = assembler.push(bytes.subspan(offset, size));
    offset += taken;
    piece = piece % 13 + 1;
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
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const Bytes bytes(data, size);
  parse_all(bytes);
  assemble(scan_request_frame, bytes, true);
  assemble(scan_reply_frame, bytes, false);
  return 0;
}
