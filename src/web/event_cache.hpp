// The SSE frame of an item ("id: ...\nevent: ...\ndata: {...}\n\n"), made once and
// shared by every stream client: ten clients of a 1 kHz sensor format 1000 frames
// a second, not 10,000. Used on the event loop's thread only, so it needs no lock.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <unordered_map>

#include "rangekit/hub/fanout.hpp"

namespace rangekit::web {

class EventCache {
 public:
  explicit EventCache(std::size_t capacity = 16384) : capacity_(capacity) {}
  const std::string& frame(const hub::HubItem& item);

 private:
  std::size_t capacity_;
  std::unordered_map<std::uint64_t, std::string> frames_;
  std::deque<std::uint64_t> order_;  // oldest first, for eviction
};

}  // namespace rangekit::web
