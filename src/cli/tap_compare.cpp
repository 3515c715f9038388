#include "cli/tap_compare.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>

#include "cli/describe.hpp"

namespace rangekit::cli {
namespace {

// Each run of digits as one '#': "$BM,12.345" and "$BM,7.5" have the same shape.
std::string shape_of(std::string_view frame) {
  std::string shape;
  for (const char c : frame) {
    const bool digit = std::isdigit(static_cast<unsigned char>(c)) != 0;
    if (digit && !shape.empty() && shape.back() == '#') continue;
    shape += digit ? '#' : c;
  }
  return shape;
}

// The frames of a byte stream, each with the time of the chunk that completed it.
template <class Take>
void frames_of(ScanFunction scan, std::string& pending, std::string_view bytes, Take take) {
  pending += bytes;
  std::size_t at = 0;
  while (at < pending.size()) {
    const FrameScan found = scan(as_bytes(std::string_view(pending).substr(at)));
    if (found.status == FrameStatus::need_more) break;
    if (found.status == FrameStatus::complete)
      take(as_text(found.frame), std::string_view(pending).substr(at, found.consumed));
    at += found.consumed;
  }
  pending.erase(0, at);
}

}  // namespace

std::vector<Exchange> exchanges_of(const record::SerialRecording& recording, const FrameDecoder& host,
                                   const FrameDecoder& sensor) {
  std::vector<Exchange> exchanges;
  std::string host_pending;
  std::string sensor_pending;
  std::chrono::system_clock::time_point asked{};
  for (const record::SerialChunk& chunk : recording.chunks) {
    if (chunk.sender == record::Sender::host) {
      frames_of(host.scan, host_pending, chunk.bytes, [&](std::string_view frame, std::string_view wire) {
        exchanges.push_back(Exchange{std::string(wire), std::string(frame), {}});
        asked = chunk.time;
      });
    } else {
      frames_of(sensor.scan, sensor_pending, chunk.bytes, [&](std::string_view frame, std::string_view /*wire*/) {
        if (exchanges.empty()) return;
        exchanges.back().answer.push_back(
            TimedFrame{std::chrono::duration_cast<std::chrono::microseconds>(chunk.time - asked), std::string(frame)});
      });
    }
  }
  return exchanges;
}

std::vector<std::string> differences(const Exchange& recorded, const std::vector<TimedFrame>& emulated,
                                     const FrameDecoder& sensor) {
  std::vector<std::string> found;
  const std::string asked = printable(as_bytes(recorded.request));
  const bool stream = recorded.answer.size() > compared_frames;
  if (stream ? emulated.empty() : emulated.size() != recorded.answer.size()) {
    found.push_back(fmt::format(
        "{}: {} frame(s) recorded, the emulator answered {}", asked,
        stream ? fmt::format("a stream of {}", recorded.answer.size()) : std::to_string(recorded.answer.size()),
        emulated.size()));
  }
  const std::size_t count = std::min({recorded.answer.size(), emulated.size(), compared_frames});
  for (std::size_t i = 0; i < count; ++i) {
    const std::string& was = recorded.answer[i].bytes;
    const std::string& is = emulated[i].bytes;
    const bool measured = sensor.measured && sensor.measured(as_bytes(was)) && sensor.measured(as_bytes(is));
    if (measured ? shape_of(was) == shape_of(is) : was == is) continue;
    found.push_back(fmt::format("{}: frame {}{}: recorded {} ({}), the emulator {} ({})", asked, i + 1,
                                measured ? ", a measurement's shape" : "", printable(as_bytes(was)),
                                sensor.describe(as_bytes(was)), printable(as_bytes(is)),
                                sensor.describe(as_bytes(is))));
  }
  if (!recorded.answer.empty() && !emulated.empty()) {
    // A pty has no line delay and a real line some: only a gross difference is a finding.
    const double was_ms = std::chrono::duration<double, std::milli>(recorded.answer.front().after).count();
    const double is_ms = std::chrono::duration<double, std::milli>(emulated.front().after).count();
    if (std::abs(was_ms - is_ms) > std::max(50.0, was_ms / 2)) {
      found.push_back(
          fmt::format("{}: first reply after {:.1f} ms recorded, {:.1f} ms from the emulator", asked, was_ms, is_ms));
    }
  }
  return found;
}

}  // namespace rangekit::cli
