#include "rangekit/core/sample.hpp"

#include <utility>

namespace rangekit {

const char* sample_kind_name(SampleKind kind) noexcept {
  switch (kind) {
    case SampleKind::uls_averaging:
      return "averaging";
    case SampleKind::uls_binning:
      return "binning";
    case SampleKind::uls_look_down:
      return "look-down";  // the mode's value name (mode=look-down)
    case SampleKind::uls_error:
      return "error";
    case SampleKind::ls5_result:
      return "result";
    case SampleKind::ls5_derivative:
      return "derivative";
  }
  return "unknown";
}

const char* signal_state_name(SignalState state) noexcept {
  switch (state) {
    case SignalState::ok:
      return "ok";
    case SignalState::none_yet:
      return "none_yet";
    case SignalState::lost:
      return "lost";
  }
  return "unknown";
}

const char* stream_event_kind_name(StreamEventKind kind) noexcept {
  switch (kind) {
    case StreamEventKind::connected:
      return "connected";
    case StreamEventKind::disconnected:
      return "disconnected";
    case StreamEventKind::reconnected:
      return "reconnected";
    case StreamEventKind::bad_frame:
      return "bad_frame";
    case StreamEventKind::lost_records:
      return "lost_records";
    case StreamEventKind::device_error:
      return "device_error";
    case StreamEventKind::polling:
      return "polling";
  }
  return "unknown";
}

bool SampleSource::next_batch(std::vector<StreamItem>& batch, std::chrono::milliseconds timeout) {
  batch.clear();
  auto item = next(timeout);
  if (!item) return false;
  batch.push_back(std::move(*item));
  return true;
}

}  // namespace rangekit
