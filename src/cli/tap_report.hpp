// What `rangekit tap` says about a conversation: each frame either side sent, decoded by the
// family's codecs; a reply paired with its request and the round trip; a stream summarised
// (its rate, every Nth frame) in text; bytes no frame holds as hex with the reason.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "cli/cli_family.hpp"
#include "rangekit/core/framer.hpp"
#include "rangekit/record/pcapng.hpp"

namespace rangekit::cli {

enum class TapFormat { text, jsonl };

struct TapCounts {
  std::uint64_t host_frames = 0;
  std::uint64_t sensor_frames = 0;
  std::uint64_t replies = 0;   // sensor frames that answered a host frame
  std::uint64_t streamed = 0;  // sensor frames no request asked for
  std::uint64_t rejected = 0;  // runs of bytes no frame holds, either side
};

class TapReport {
 public:
  TapReport(FrameDecoder host, FrameDecoder sensor, TapFormat format, std::uint64_t every, bool colour);
  // The lines (without '\n') the chunk completes; a chunk may end inside a frame.
  std::vector<std::string> add(const record::SerialChunk& chunk);
  // The last stream summary and the bytes left inside an unfinished frame.
  std::vector<std::string> finish();
  [[nodiscard]] const TapCounts& counts() const noexcept { return counts_; }

 private:
  void frame(record::Sender sender, std::chrono::system_clock::time_point time, Bytes bytes,
             std::vector<std::string>& out);
  void rejected(record::Sender sender, std::chrono::system_clock::time_point time, std::size_t count,
                const char* reason, std::string_view bytes, std::vector<std::string>& out);
  void stream_summary(std::chrono::system_clock::time_point now, bool last, std::vector<std::string>& out);
  [[nodiscard]] std::string prefix(record::Sender sender, std::chrono::system_clock::time_point time) const;

  DecodingSide host_;
  DecodingSide sensor_;
  TapFormat format_;
  std::uint64_t every_;
  bool colour_;
  TapCounts counts_;
  // Host frames not answered yet, oldest first: a host may send the next request before the
  // reply to the last (both families answer in order).
  std::deque<std::chrono::system_clock::time_point> requests_;
  // The stream since the last summary (text): frames and when the period began.
  std::uint64_t stream_frames_ = 0;
  std::optional<std::chrono::system_clock::time_point> stream_since_;
  std::string recent_;  // the bytes of the chunk being read, for a rejection's hex
};

}  // namespace rangekit::cli
