// Test rig for the ULS firmware model: feeds bytes, runs virtual time the way
// the runtime does (deadline by deadline) and collects what the ports send.
#pragma once
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "rangekit/uls/emulator/firmware.hpp"
#include "rangekit/uls/uls.hpp"

namespace rangekit::uls::emulator::testing {

struct TimedLine {
  std::string text;  // without the CR
  Nanos done{0};     // when its CR left the line
};

struct Unit {
  explicit Unit(FirmwareOptions options = {}) : firmware(std::make_unique<Firmware>(std::move(options))) {}

  // Runs every deadline up to now + span, collecting output as the runtime does.
  void run(Nanos span) {
    const Nanos until = now + span;
    while (true) {
      const Nanos deadline = firmware->next_deadline();
      if (deadline > until) break;
      now = std::max(now, deadline);
      firmware->advance(now);
      collect();
    }
    now = until;
    firmware->advance(now);
    collect();
  }
  void collect() {
    for (std::size_t port = 0; port < 2; ++port) firmware->take_line_output(port, now, output[port]);
  }
  void send(std::size_t port, std::string_view text) {
    for (const char c : text) firmware->receive(port, static_cast<std::uint8_t>(c), now);
  }
  std::vector<LineByte> take(std::size_t port) {
    collect();
    auto bytes = std::move(output[port]);
    output[port].clear();
    return bytes;
  }
  std::string text(std::size_t port) {
    std::string text;
    for (const auto& b : take(port)) text.push_back(static_cast<char>(b.value));
    return text;
  }
  // Sends a command (CR added), waits 50 ms and returns the reply lines without CRs.
  std::string ask(std::string_view command, std::size_t port = configuration_port) {
    (void)take(port);
    send(port, command);
    send(port, "\r");
    run(std::chrono::milliseconds(50));
    std::string reply = text(port);
    if (!reply.empty() && reply.back() == '\r') reply.pop_back();
    return reply;
  }
  std::vector<TimedLine> lines_with_times(std::size_t port) {
    std::vector<TimedLine> lines;
    std::string& current = partial[port];  // a line still on the wire stays for the next call
    for (const auto& b : take(port)) {
      if (b.value == '\r') {
        lines.push_back(TimedLine{current, b.done});
        current.clear();
      } else {
        current.push_back(static_cast<char>(b.value));
      }
    }
    return lines;
  }
  std::vector<std::string> lines(std::size_t port) {
    std::vector<std::string> texts;
    for (auto& line : lines_with_times(port)) texts.push_back(std::move(line.text));
    return texts;
  }

  std::unique_ptr<Firmware> firmware;
  Nanos now{0};
  std::vector<LineByte> output[2];
  std::string partial[2];
};

// The range of a range-only averaging line ("$BM,25.001" or "#QBM,25.001"), -1 if none.
inline double metres_of(const std::string& line) {
  const MeasurementContext context{Mode::averaging, DisplayMode::range, Units::metres, false};
  auto m = decode_measurement(as_bytes(line), context);
  if (!m) return -1;
  const auto* reading = std::get_if<AveragingReading>(&m->reading);
  return reading && reading->range ? reading->range->metres : -1;
}

}  // namespace rangekit::uls::emulator::testing
