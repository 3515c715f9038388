// One measurement as the host received it, in a form both families share, so
// stream output (jsonl/csv/text), SQLite capture and replay handle ULS and LS5
// alike. Field names follow the JSON keys of docs/cli.md.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include "rangekit/core/shared_name.hpp"

namespace rangekit {

enum class SampleKind : std::uint8_t {
  uls_averaging,   // distance_m and/or pulse_width
  uls_binning,     // targets (one complete target array)
  uls_look_down,   // presence and/or pulses_between_events (or pulses_overflow)
  uls_error,       // device_error (e.g. $ER,4 target not found)
  ls5_result,      // code, distance_mm, signal
  ls5_derivative,  // code, derivative_mm, signal: «Type of preliminary result» 01 (LS5 §8.8/§8.9)
};

const char* sample_kind_name(SampleKind kind) noexcept;

struct TargetHit {
  double distance_m = 0;
  std::uint32_t strength = 0;
  friend bool operator==(const TargetHit&, const TargetHit&) = default;
};

// The targets of one binning burst. The ULS reports at most 15 (uls-interface-spec §3
// "the maximum number of targets allowed in Binning Mode is 15", §9 "Up to 15 targets
// maximum"; the decoder refuses a larger count), so they are kept inside the Sample:
// a burst on the live path allocates nothing. More (a hand-made capture)
// still fit: they go to the heap.
class TargetList {
 public:
  static constexpr std::size_t inline_capacity = 15;
  using value_type = TargetHit;
  using iterator = TargetHit*;
  using const_iterator = const TargetHit*;

  TargetList() = default;
  TargetList(std::initializer_list<TargetHit> hits) { assign(hits.begin(), hits.end()); }
  TargetList& operator=(std::initializer_list<TargetHit> hits) {
    assign(hits.begin(), hits.end());
    return *this;
  }

  template <typename Iterator>
  void assign(Iterator first, Iterator last) {
    clear();
    for (; first != last; ++first) push_back(*first);
  }
  void push_back(const TargetHit& hit) {
    if (size_ < inline_capacity) {
      inline_[size_] = hit;
    } else {
      if (size_ == inline_capacity) overflow_.assign(inline_.begin(), inline_.end());
      overflow_.push_back(hit);
    }
    ++size_;
  }
  void clear() noexcept {
    size_ = 0;
    overflow_.clear();
  }

  [[nodiscard]] std::size_t size() const noexcept { return size_; }
  [[nodiscard]] bool empty() const noexcept { return size_ == 0; }
  [[nodiscard]] TargetHit* data() noexcept { return size_ > inline_capacity ? overflow_.data() : inline_.data(); }
  [[nodiscard]] const TargetHit* data() const noexcept {
    return size_ > inline_capacity ? overflow_.data() : inline_.data();
  }
  [[nodiscard]] iterator begin() noexcept { return data(); }
  [[nodiscard]] iterator end() noexcept { return data() + size_; }
  [[nodiscard]] const_iterator begin() const noexcept { return data(); }
  [[nodiscard]] const_iterator end() const noexcept { return data() + size_; }
  [[nodiscard]] TargetHit& operator[](std::size_t index) noexcept { return data()[index]; }
  [[nodiscard]] const TargetHit& operator[](std::size_t index) const noexcept { return data()[index]; }
  [[nodiscard]] const TargetHit& front() const noexcept { return data()[0]; }
  [[nodiscard]] const TargetHit& back() const noexcept { return data()[size_ - 1]; }

  friend bool operator==(const TargetList& a, const TargetList& b) noexcept {
    return std::equal(a.begin(), a.end(), b.begin(), b.end());
  }

 private:
  std::array<TargetHit, inline_capacity> inline_{};
  std::size_t size_ = 0;
  std::vector<TargetHit> overflow_;  // all of them, once there are more than inline_capacity
};

// LS5 result-code meaning (§9.3): a distance, 65534 no measurement yet, 65535 no signal.
enum class SignalState : std::uint8_t { ok, none_yet, lost };
const char* signal_state_name(SignalState state) noexcept;

struct Sample {
  std::chrono::system_clock::time_point time;  // host receive time (UTC)
  std::string device;                          // "uls" or "ls5"
  SharedName source;  // port path or UDP endpoint it came from; shared, so a copy does not allocate
  int address = -1;   // bus address, -1 when the protocol has none
  SampleKind kind = SampleKind::uls_averaging;

  // ULS averaging
  std::optional<double> distance_m;
  std::optional<std::uint32_t> pulse_width;  // as on the wire (picoseconds)
  // ULS binning
  TargetList targets;
  // ULS look down
  std::optional<bool> presence;
  std::optional<std::uint32_t> pulses_between_events;
  // `$0000`: more than 65535 pulses between the edges (§8 "signifying maximum time
  // occurred"); pulses_between_events is then empty (U88).
  bool pulses_overflow = false;
  // ULS measurement error number ($ER,n)
  std::optional<int> device_error;
  // LS5
  std::optional<std::uint16_t> code;
  std::optional<double> distance_mm;    // ls5_result: formula 8.1; null on 65534/65535
  std::optional<double> derivative_mm;  // ls5_derivative: formula 8.2; null on 65534/65535
  std::optional<SignalState> signal;
  // The sensor's discreteness (LS5 table 3.1): how many decimals its millimetres deserve.
  std::optional<double> resolution_mm;
  // Quality (docs/reliability.md): the frame decoded, but the value is one no real target
  // gives here (core/sample_quality.hpp); suspect_reason says which check and why.
  // Neither protocol has a checksum, so this is the only sign of a corrupted line.
  bool suspect = false;
  std::string suspect_reason;

  friend bool operator==(const Sample&, const Sample&) = default;
};

// A link event a stream reports besides samples: the cable went away, came back,
// a frame did not decode, records were lost (UDP counter gap, queue overflow).
enum class StreamEventKind : std::uint8_t {
  connected,
  disconnected,
  reconnected,
  bad_frame,
  lost_records,
  device_error,
  polling  // the stream switched to asking for each measurement (ULS: no continuous lines here, U62)
};
const char* stream_event_kind_name(StreamEventKind kind) noexcept;

struct StreamEvent {
  std::chrono::system_clock::time_point time;
  StreamEventKind kind = StreamEventKind::connected;
  std::string message;
  std::uint64_t count = 0;  // lost records for lost_records
};

}  // namespace rangekit

#include <memory>
#include <variant>

namespace rangekit {

using StreamItem = std::variant<Sample, StreamEvent>;

// Anything that yields samples: a live ULS or LS5 stream, a UDP receiver, a
// capture being replayed. The stream CLI and the capture writer consume this.
class SampleSource {
 public:
  SampleSource() = default;
  SampleSource(const SampleSource&) = delete;
  SampleSource& operator=(const SampleSource&) = delete;
  virtual ~SampleSource() = default;

  // The next sample or event, waiting up to `timeout`; nullopt when nothing came
  // in time, or at once when finished() and nothing is left.
  virtual std::optional<StreamItem> next(std::chrono::milliseconds timeout) = 0;
  // The next items, in order, waiting up to `timeout` for the first: `batch` is
  // replaced (pass the same vector each time; its storage is reused). False, with
  // `batch` empty, when next() would have returned nullopt. A live stream hands over
  // everything its reader queued with one wake-up and one lock; this
  // default takes one item.
  virtual bool next_batch(std::vector<StreamItem>& batch, std::chrono::milliseconds timeout);
  // True once the source has ended for good (replay reached its end, the device
  // stream stopped and will not reconnect). Items may still be queued.
  [[nodiscard]] virtual bool finished() const = 0;
  // Asks the source to stop (Ctrl-C); it finishes soon after.
  virtual void stop() = 0;
  // Records lost inside the source (queue overflow, UDP counter gaps).
  [[nodiscard]] virtual std::uint64_t lost() const { return 0; }
};

using SampleSourcePtr = std::unique_ptr<SampleSource>;

}  // namespace rangekit
