#include "rangekit/core/sample.hpp"

#include <utility>

namespace rangekit {

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
