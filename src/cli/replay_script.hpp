// A recorded conversation as what a sensor said after each request (`rangekit sim replay`):
// each host frame with the sensor's bytes that followed it until the next one, each at its
// recorded delay, so a reply comes back at once and a stream at its recorded pace.
#pragma once

#include <chrono>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "rangekit/core/framer.hpp"
#include "rangekit/record/pcapng.hpp"

namespace rangekit::cli {

struct TimedBytes {
  std::chrono::microseconds after{0};  // from the request (or from the start, before any)
  std::string bytes;
};
using Answer = std::vector<TimedBytes>;

class ReplayScript {
 public:
  // `host_scan` frames what the host sent (the family's host-side framer).
  static ReplayScript from_recording(const record::SerialRecording& recording, ScanFunction host_scan);

  // What the sensor said before the host asked anything.
  [[nodiscard]] const Answer& opening() const noexcept { return opening_; }
  // The answer to a request: each recorded answer to it in turn, then the last one again; none
  // for a request the recording never heard.
  const Answer* answer(const std::string& request);
  [[nodiscard]] std::size_t requests() const noexcept { return requests_; }

 private:
  Answer opening_;
  std::map<std::string, std::deque<Answer>, std::less<>> answers_;
  std::size_t requests_ = 0;
  Answer last_;  // the answer handed out last, once taken from its queue
};

}  // namespace rangekit::cli
