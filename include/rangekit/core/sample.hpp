// One measurement as the host received it: its time, source and kind, and a value for each
// of its family's channels (core/channel.hpp), so stream output, capture and every face
// handle any family alike.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "rangekit/core/shared_name.hpp"

namespace rangekit {

// What a sample is, as its family numbers its kinds (FamilyDescriptor::kinds): a ULS
// averaging line, an LS5 derivative. Generic code names it through the family.
enum class SampleKind : std::uint8_t {};

// A channel of a family (the index of its ChannelDescriptor), typed by how the family's own
// code reads it: a distance as a double, a flag as a bool, a count as an integer.
// The key names its family: a sample of another family has no value for it (its channel of the
// same index means something else).
template <class T>
struct ChannelKey {
  std::string_view family;
  std::uint8_t index = 0;
  // The key's value is the channel's × scale: a pulse width kept in ns, read in ps (1000).
  double scale = 1;
};

// The channels a sample has a value for, each in its channel's unit: a fixed slot per
// channel, so a sample allocates nothing for them and a copy is a copy of bytes.
class ChannelValues {
 public:
  static constexpr std::size_t capacity = 16;

  [[nodiscard]] std::optional<double> get(std::size_t channel) const noexcept {
    if (!has(channel)) return std::nullopt;
    return values_[channel];
  }
  [[nodiscard]] bool has(std::size_t channel) const noexcept {
    return channel < capacity && (present_ & (1U << channel)) != 0;
  }
  // A channel beyond the capacity is not kept (a family has at most `capacity`, checked
  // when it registers).
  void set(std::size_t channel, double value) noexcept {
    if (channel >= capacity) return;
    values_[channel] = value;
    present_ = static_cast<std::uint16_t>(present_ | (1U << channel));
  }
  void erase(std::size_t channel) noexcept {
    if (channel < capacity) present_ = static_cast<std::uint16_t>(present_ & ~(1U << channel));
  }
  void clear() noexcept { present_ = 0; }
  [[nodiscard]] bool empty() const noexcept { return present_ == 0; }

  friend bool operator==(const ChannelValues& a, const ChannelValues& b) noexcept {
    if (a.present_ != b.present_) return false;
    for (std::size_t channel = 0; channel < capacity; ++channel) {
      if (a.has(channel) && a.values_[channel] != b.values_[channel]) return false;
    }
    return true;
  }

 private:
  std::array<double, capacity> values_{};
  std::uint16_t present_ = 0;
};

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

struct Sample {
  std::chrono::system_clock::time_point time;  // host receive time (UTC)
  std::string device;                          // its family's name: "uls", "ls5"
  SharedName source;  // port path or UDP endpoint it came from; shared, so a copy does not allocate
  int address = -1;   // bus address, -1 when the protocol has none
  SampleKind kind{};  // one of its family's kinds

  // Its channels' values, in each channel's unit (the family's channel descriptors).
  ChannelValues values;
  // The targets of one burst, for a family whose channels include targets.
  TargetList targets;
  // Quality (docs/reliability.md): the frame decoded, but the value is one no real target
  // gives here (core/sample_quality.hpp); suspect_reason says which check and why.
  // Neither protocol has a checksum, so this is the only sign of a corrupted line.
  bool suspect = false;
  std::string suspect_reason;

  template <class T>
  [[nodiscard]] std::optional<T> get(ChannelKey<T> key) const noexcept {
    if (!is_of(key.family)) return std::nullopt;
    const auto value = values.get(key.index);
    if (!value) return std::nullopt;
    if constexpr (std::is_same_v<T, bool>) {
      return *value != 0;
    } else if constexpr (std::is_enum_v<T>) {
      return static_cast<T>(static_cast<std::underlying_type_t<T>>(*value));
    } else if constexpr (std::is_integral_v<T>) {
      return static_cast<T>(std::llround(*value * key.scale));  // ps of 12.345 ns: 12345, not 12344
    } else {
      return static_cast<T>(*value * key.scale);
    }
  }
  // Whether the sample is of this family: a short name compared in place, as a bulk read asks
  // it for every channel of millions of samples.
  [[nodiscard]] bool is_of(std::string_view family) const noexcept {
    if (device.size() != family.size()) return false;
    for (std::size_t at = 0; at < family.size(); ++at) {
      if (device[at] != family[at]) return false;
    }
    return true;
  }

  // Sets the channel, or clears it for nullopt; nothing for a key of another family than `device`.
  template <class T>
  void set(ChannelKey<T> key, std::type_identity_t<std::optional<T>> value) noexcept {
    if (!is_of(key.family)) return;
    if (!value) {
      values.erase(key.index);
      return;
    }
    values.set(key.index, number_of(*value) / key.scale);
  }

  friend bool operator==(const Sample&, const Sample&) = default;

 private:
  // A key's value as the number kept: a flag 1 or 0, a state its number.
  template <class T>
  static double number_of(T value) noexcept {
    if constexpr (std::is_same_v<T, bool>) {
      return value ? 1.0 : 0.0;
    } else if constexpr (std::is_enum_v<T>) {
      return static_cast<double>(static_cast<std::underlying_type_t<T>>(value));
    } else {
      return static_cast<double>(value);
    }
  }
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
