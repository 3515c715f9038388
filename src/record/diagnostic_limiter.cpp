#include "rangekit/record/diagnostic_limiter.hpp"

#include <cstdio>

#include "rangekit/record/format.hpp"

namespace rangekit::record {
namespace {

const char* plural_name(StreamEventKind kind) {
  switch (kind) {
    case StreamEventKind::connected:
      return "connects";
    case StreamEventKind::disconnected:
      return "disconnects";
    case StreamEventKind::reconnected:
      return "reconnects";
    case StreamEventKind::bad_frame:
      return "bad frames";
    case StreamEventKind::lost_records:
      return "lost-record reports";
    case StreamEventKind::device_error:
      return "device errors";
    case StreamEventKind::polling:
      return "polling notices";
  }
  return "events";
}

}  // namespace

std::string merged_events_text(StreamEventKind kind, std::uint64_t count, double seconds) {
  char text[96];
  std::snprintf(text, sizeof text, "%llu more %s in the last %.3g s\n", static_cast<unsigned long long>(count),
                plural_name(kind), seconds);
  return text;
}

void DiagnosticLimiter::summarise(std::size_t kind, TimePoint now, std::vector<std::string>& lines) {
  KindState& state = kinds_[kind];
  if (state.unprinted == 0) return;
  const double seconds = std::chrono::duration<double>(now - state.since).count();
  lines.push_back(merged_events_text(static_cast<StreamEventKind>(kind), state.unprinted, seconds));
  state.unprinted = 0;
}

std::vector<std::string> DiagnosticLimiter::tick(TimePoint now) {
  std::vector<std::string> lines;
  for (std::size_t kind = 0; kind < kind_count; ++kind) {
    KindState& state = kinds_[kind];
    if (!state.open || now - state.since < window_) continue;
    // A window with repeats ends in its summary and the next window counts on;
    // a quiet window closes, so the next event of the kind is printed in full.
    state.open = state.unprinted > 0;
    summarise(kind, now, lines);
    state.since = now;
  }
  return lines;
}

std::vector<std::string> DiagnosticLimiter::on_event(const StreamEvent& event, TimePoint now) {
  std::vector<std::string> lines = tick(now);
  const auto kind = static_cast<std::size_t>(event.kind);
  if (kind >= kind_count) return lines;
  // A link's comings and goings are few and each names its sensor: merged, "1 more connects"
  // would hide which of several sensors came up or went away.
  if (event.kind == StreamEventKind::connected || event.kind == StreamEventKind::disconnected ||
      event.kind == StreamEventKind::reconnected) {
    std::string line;
    append_text(line, event);
    lines.push_back(std::move(line));
    return lines;
  }
  KindState& state = kinds_[kind];
  if (state.open) {
    ++state.unprinted;
    ++merged_;
    return lines;
  }
  state.open = true;
  state.since = now;
  std::string line;
  append_text(line, event);
  lines.push_back(std::move(line));
  return lines;
}

std::vector<std::string> DiagnosticLimiter::finish(TimePoint now) {
  std::vector<std::string> lines;
  for (std::size_t kind = 0; kind < kind_count; ++kind) {
    summarise(kind, now, lines);
    kinds_[kind].open = false;
  }
  return lines;
}

}  // namespace rangekit::record
