// A Transport for the fuzzers that plays the device's side from the fuzz input. The input
// is split into segments at each 0xFF 0xFF: segment 0 is what the line carries before the
// host writes, each write moves on to the next segment (the "answer" to it). Reads hand a
// segment out in pieces (sizes cycle 1..29, so frames straddle reads); when it is used up
// they fail at once with `exhausted` (Errc::timeout: "nothing more came", Errc::closed:
// the line went away). No read waits on a clock, so an input runs in microseconds.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "rangekit/core/transport.hpp"

namespace rangekit::fuzz {

class ScriptedTransport final : public Transport {
 public:
  ScriptedTransport(Bytes script, Errc exhausted) : exhausted_(exhausted) {
    std::size_t start = 0;
    for (std::size_t i = 0; i + 1 < script.size(); ++i) {
      if (script[i] == 0xFF && script[i + 1] == 0xFF) {
        segments_.push_back(script.subspan(start, i - start));
        start = i + 2;
        ++i;
      }
    }
    segments_.push_back(script.subspan(std::min(start, script.size())));
  }
  Status write_all(Bytes) override {
    if (closed_) return make_error(Errc::closed, "closed");
    if (segment_ + 1 < segments_.size()) {
      ++segment_;
      at_ = 0;
    } else {
      at_ = segments_[segment_].size();  // nothing answers a write past the script
    }
    return ok_status();
  }
  Result<std::size_t> read_some(std::span<std::uint8_t> out, std::chrono::milliseconds) override {
    if (closed_) return make_error(Errc::closed, "closed");
    const Bytes segment = segments_[segment_];
    if (at_ >= segment.size()) return make_error(exhausted_, "nothing more in the script");
    piece_ = piece_ % 29 + 1;
    const std::size_t size = std::min({out.size(), piece_, segment.size() - at_});
    std::memcpy(out.data(), segment.data() + at_, size);
    at_ += size;
    return size;
  }
  void close() noexcept override { closed_ = true; }
  [[nodiscard]] std::string name() const override { return "fuzz script"; }

 private:
  Errc exhausted_;
  std::vector<Bytes> segments_;
  std::size_t segment_ = 0;
  std::size_t at_ = 0;
  std::size_t piece_ = 0;
  bool closed_ = false;
};

}  // namespace rangekit::fuzz
