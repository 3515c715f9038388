#include "cli/tap_report.hpp"

#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include "cli/describe.hpp"
#include "rangekit/record/format.hpp"

namespace rangekit::cli {
namespace {

std::string hex_of(std::string_view bytes) {
  std::string out;
  for (const char c : bytes) out += fmt::format("{}{:02x}", out.empty() ? "" : " ", static_cast<unsigned char>(c));
  return out;
}

constexpr std::size_t max_unanswered = 64;

double milliseconds(std::chrono::system_clock::duration span) {
  return std::chrono::duration<double, std::milli>(span).count();
}

}  // namespace

TapReport::TapReport(FrameDecoder host, FrameDecoder sensor, TapFormat format, std::uint64_t every, bool colour)
    : host_(std::move(host)),
      sensor_(std::move(sensor)),
      format_(format),
      every_(every == 0 ? 1 : every),
      colour_(colour) {}

std::string TapReport::prefix(record::Sender sender, std::chrono::system_clock::time_point time) const {
  std::string stamp;
  record::append_iso_time(stamp, time);
  const bool host = sender == record::Sender::host;
  // Host in cyan, sensor in yellow: who spoke is what one looks for first.
  const char* colour = !colour_ ? "" : host ? "\x1b[36m" : "\x1b[33m";
  return fmt::format("{}{} {:<6} {}", colour, stamp, record::sender_name(sender), host ? ">" : "<");
}

void TapReport::frame(record::Sender sender, std::chrono::system_clock::time_point time, Bytes bytes,
                      std::vector<std::string>& out) {
  const bool host = sender == record::Sender::host;
  const std::string decoded = (host ? host_ : sensor_).decoder.describe(bytes);
  std::optional<double> round_trip;
  bool streamed = false;
  if (host) {
    ++counts_.host_frames;
    if (requests_.size() == max_unanswered) requests_.pop_front();  // a host that never hears back
    requests_.push_back(time);
  } else {
    ++counts_.sensor_frames;
    if (!requests_.empty()) {
      ++counts_.replies;
      round_trip = milliseconds(time - requests_.front());
      requests_.pop_front();
    } else {
      ++counts_.streamed;
      streamed = true;
    }
  }
  if (format_ == TapFormat::jsonl) {
    std::string stamp;
    record::append_iso_time(stamp, time);
    nlohmann::json record{{"time", stamp},
                          {"direction", record::sender_name(sender)},
                          {"raw", printable(bytes)},
                          {"hex", hex_of(as_text(bytes))},
                          {"decoded", decoded}};
    if (round_trip) record["rtt_ms"] = *round_trip;
    if (streamed) record["streamed"] = true;
    out.push_back(record.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    return;
  }
  if (streamed) {
    if (!stream_since_) stream_since_ = time;
    ++stream_frames_;
    stream_summary(time, false, out);
    if ((counts_.streamed - 1) % every_ != 0) return;  // the 1st, then every Nth
  } else {
    stream_summary(time, true, out);
  }
  std::string line = fmt::format("{} {:<24} {}", prefix(sender, time), printable(bytes), decoded);
  if (round_trip) line += fmt::format("  ({:.1f} ms)", *round_trip);
  if (streamed && every_ > 1) line += fmt::format("  (streamed, 1 in {})", every_);
  if (colour_) line += "\x1b[0m";
  out.push_back(std::move(line));
}

void TapReport::stream_summary(std::chrono::system_clock::time_point now, bool last, std::vector<std::string>& out) {
  if (!stream_since_) return;
  const double seconds = std::chrono::duration<double>(now - *stream_since_).count();
  if (!last && seconds < 1.0) return;
  if (stream_frames_ > 0 && seconds > 0) {
    out.push_back(fmt::format("{}   sensor streaming: {} frames in {:.1f} s, {:.0f} frames/s", std::string(26, ' '),
                              stream_frames_, seconds, static_cast<double>(stream_frames_) / seconds));
  }
  stream_frames_ = 0;
  stream_since_ = last ? std::nullopt : std::optional(now);
}

void TapReport::rejected(record::Sender sender, std::chrono::system_clock::time_point time, std::size_t count,
                         const char* reason, std::string_view bytes, std::vector<std::string>& out) {
  ++counts_.rejected;
  const std::string why = reason == nullptr ? "not a frame" : reason;
  if (format_ == TapFormat::jsonl) {
    std::string stamp;
    record::append_iso_time(stamp, time);
    out.push_back(nlohmann::json{
        {"time", stamp},
        {"direction", record::sender_name(sender)},
        {"hex", hex_of(bytes)},
        {"rejected", why},
        {"bytes",
         count}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    return;
  }
  out.push_back(fmt::format("{} !! {} byte(s) [{}]: {}{}", prefix(sender, time), count, hex_of(bytes), why,
                            colour_ ? "\x1b[0m" : ""));
}

std::vector<std::string> TapReport::add(const record::SerialChunk& chunk) {
  std::vector<std::string> out;
  DecodingSide& side = chunk.sender == record::Sender::host ? host_ : sensor_;
  FrameAssembler::Event event;
  feed_all(side.assembler, as_bytes(chunk.bytes), [&] {
    for (;;) {
      const Bytes before = side.assembler.pending();
      if (!side.assembler.next(event)) break;
      if (event.kind == FrameAssembler::Event::Kind::frame) {
        frame(chunk.sender, chunk.time, event.frame, out);
        continue;
      }
      // The rejected bytes end where the buffer now begins (line endings before them are
      // skipped silently), or are all it held when it filled up without a frame end.
      const std::uint8_t* after = side.assembler.pending().data();
      const std::size_t count = event.rejected_bytes;
      const bool behind = after >= before.data() + count && after <= before.data() + before.size();
      const Bytes bytes = behind ? Bytes(after - count, count) : before.first(std::min(count, before.size()));
      rejected(chunk.sender, chunk.time, count, event.reason, as_text(bytes), out);
    }
  });
  return out;
}

std::vector<std::string> TapReport::finish() {
  std::vector<std::string> out;
  if (stream_since_) stream_summary(std::chrono::system_clock::now(), true, out);
  for (const auto sender : {record::Sender::host, record::Sender::sensor}) {
    DecodingSide& side = sender == record::Sender::host ? host_ : sensor_;
    if (side.assembler.buffered() > 0) {
      rejected(sender, std::chrono::system_clock::now(), side.assembler.buffered(), "the frame never ended",
               as_text(side.assembler.pending()), out);
    }
  }
  return out;
}

}  // namespace rangekit::cli
