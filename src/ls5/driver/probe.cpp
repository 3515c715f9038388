// Does an LS5 answer here? For `rangekit detect`: listens before speaking, since any
// byte would stop a running stream (L37), then asks ID only, which changes nothing.
#include <array>

#include "rangekit/ls5/driver.hpp"
#include "rangekit/ls5/frame.hpp"

namespace rangekit::ls5 {
namespace {

using Clock = std::chrono::steady_clock;

// Reads frames until `deadline`; returns the first one `wanted` accepts.
template <class Wanted>
std::optional<Reply> wait_for_reply(Transport& transport, FrameAssembler& assembler, Clock::time_point deadline,
                                    Wanted wanted, Status& link) {
  std::array<std::uint8_t, 256> buffer{};
  for (;;) {
    FrameAssembler::Event event;
    while (assembler.next(event)) {
      if (event.kind != FrameAssembler::Event::Kind::frame) continue;
      auto reply = parse_reply(event.frame);
      if (reply && wanted(*reply)) return *reply;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) return std::nullopt;
    auto got = transport.read_some(buffer, left);
    if (!got) {
      if (got.error().code != Errc::timeout) link = got.error();
      return std::nullopt;
    }
    assembler.push(Bytes(buffer.data(), *got));
  }
}

}  // namespace

Result<ProbeResult> probe(Transport& transport, std::uint8_t address, std::chrono::milliseconds timeout) {
  FrameAssembler assembler(&scan_reply_frame, 1024);
  Status link = ok_status();
  // Listen for a quarter of the timeout: a streaming sensor sends a record at least every 25.5 s
  // at the slowest setting, but in practice within milliseconds.
  const auto listen_until = Clock::now() + timeout / 4;
  auto record = wait_for_reply(
      transport, assembler, listen_until, [](const Reply& reply) { return reply.kind == ReplyKind::stream_record; },
      link);
  if (!link) return link.error();
  if (record) return ProbeResult{true, address, std::nullopt};

  const Request request = Request::simple(address, CommandId::identification);
  auto encoded = encode_request(request);
  if (!encoded) return encoded.error();
  Status written = transport.write_all(encoded->bytes());
  if (!written) return written.error();
  auto reply = wait_for_reply(
      transport, assembler, Clock::now() + timeout,
      [&request](const Reply& candidate) { return check_reply_answers(request, candidate).ok(); }, link);
  if (!link) return link.error();
  if (!reply) {
    return make_error(Errc::timeout,
                      "no LS5 answered ID at address " + std::to_string(address) + " on " + transport.name());
  }
  return ProbeResult{false, address, reply->identification};
}

}  // namespace rangekit::ls5
